/* sim_output.h - a simulation's file: declared in output.h */
#include "output.h"
