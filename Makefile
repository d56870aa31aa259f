# rps3 - one plain Makefile.  `make paper` and `make check` are the two
# commands a new user needs; both install what is missing first.

# ---------------------------------------------------------------- settings
CC ?= cc
OPT ?= -O2
WARN = -std=c99 -pedantic -Wall -Wextra -Werror -Wshadow -Wstrict-prototypes \
       -Wmissing-prototypes -Wwrite-strings -Wdouble-promotion
CPPFLAGS_ALL = -Iinclude -Isrc -D_POSIX_C_SOURCE=200809L
# recursive (=) so that they are read when a recipe runs, after `deps`
GSL_CFLAGS = $(shell gsl-config --cflags 2>/dev/null)
GSL_LIBS = $(shell gsl-config --libs 2>/dev/null)
HDF5_CFLAGS = $(shell pkg-config --cflags hdf5 2>/dev/null)
HDF5_LIBS = $(shell pkg-config --libs hdf5 2>/dev/null) -lhdf5_hl
YAML_LIBS = -lyaml
MPI_CFLAGS = $(shell pkg-config --cflags ompi-c 2>/dev/null)
MPI_LIBS = $(shell pkg-config --libs ompi-c 2>/dev/null)
CMOCKA_LIBS = -lcmocka
SAN = -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
PYTHON ?= python3
VENV = .venv
VPY = $(VENV)/bin/python

# Debian packages the build, the tests and the figures need
DEB_PKGS = gcc clang libclang-rt-dev make pkg-config libgsl-dev libhdf5-dev libyaml-dev \
           libcmocka-dev python3-venv libopenmpi-dev openmpi-bin valgrind time

B = build
LIB_SRC = $(wildcard src/*.c)
LIB_OBJ = $(LIB_SRC:src/%.c=$(B)/obj/%.o)
LIB_PIC = $(LIB_SRC:src/%.c=$(B)/pic/%.o)
LIB_SAN = $(LIB_SRC:src/%.c=$(B)/san/%.o)
TEST_SRC = $(wildcard tests/test_*.c)
TEST_BIN = $(TEST_SRC:tests/%.c=$(B)/tests/%)
TEST_SAN = $(TEST_SRC:tests/%.c=$(B)/tests-san/%)
# the control-loop example (tests/example_control_loop.c) is built like a
# test and run by check-c; it is not a sanitizer test
TEST_BIN += $(B)/tests/example_control_loop
RUN_MAINS = runner/main_run.c runner/main_study.c
RUN_COMMON = $(filter-out $(RUN_MAINS),$(wildcard runner/*.c))
RUN_OBJ = $(RUN_COMMON:runner/%.c=$(B)/runner/%.o)

.PHONY: all lib runner runner-mpi study-bin check check-c check-san check-py paper \
        study bench deps venv clean

all: lib runner runner-mpi

# ------------------------------------------------------------ dependencies
# Installs missing Debian packages when run as root; otherwise stops with the
# exact command to run.
deps: $(B)/.deps
$(B)/.deps:
	@missing=""; for p in $(DEB_PKGS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" \
	    || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing Debian packages:$$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
	      apt-get install -y -qq --no-install-recommends $$missing >/dev/null || exit 1; \
	  else \
	    echo "missing Debian packages:$$missing"; \
	    echo "run:  sudo apt-get install -y$$missing"; exit 1; \
	  fi; \
	fi
	@mkdir -p $(B) && touch $@

venv: $(VENV)/.ok
$(VENV)/.ok: analysis/requirements.txt | $(B)/.deps
	$(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install -q --disable-pip-version-check -r analysis/requirements.txt
	@touch $@

# ----------------------------------------------------------------- library
lib: $(B)/librps3.a $(B)/librps3.so

$(B)/obj/%.o: src/%.c | $(B)/.deps
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) $(GSL_CFLAGS) $(WARN) $(OPT) -MMD -MP -c $< -o $@
$(B)/pic/%.o: src/%.c | $(B)/.deps
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) $(GSL_CFLAGS) $(WARN) $(OPT) -fPIC -fvisibility=hidden -MMD -MP -c $< -o $@
$(B)/san/%.o: src/%.c | $(B)/.deps
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) $(GSL_CFLAGS) $(WARN) -O1 -g $(SAN) -MMD -MP -c $< -o $@

$(B)/librps3.a: $(LIB_OBJ)
	ar rcs $@ $^
$(B)/librps3.so: $(LIB_PIC)
	$(CC) -shared -o $@ $^ $(GSL_LIBS)
$(B)/librps3-san.a: $(LIB_SAN)
	ar rcs $@ $^

# ------------------------------------------------------------------ runner
runner: $(B)/rps3-run

$(B)/runner/%.o: runner/%.c | $(B)/.deps
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) -Irunner $(GSL_CFLAGS) $(HDF5_CFLAGS) $(WARN) $(OPT) -MMD -MP -c $< -o $@
$(B)/rps3-run: $(B)/runner/main_run.o $(RUN_OBJ) $(B)/librps3.a
	$(CC) -o $@ $^ $(HDF5_LIBS) $(YAML_LIBS) $(GSL_LIBS) -lpthread -lm
$(B)/rps3-study: $(B)/runner/main_study.o $(RUN_OBJ) $(B)/librps3.a
	$(CC) -o $@ $^ $(HDF5_LIBS) $(YAML_LIBS) $(GSL_LIBS) -lpthread -lm

# rps3-run-mpi: the same program built with -DRPS3_MPI, for
# `mpirun -n N build/rps3-run-mpi SCENE.yaml -o OUT.h5` (Debian's OpenMPI)
runner-mpi: $(B)/rps3-run-mpi
$(B)/runner-mpi/main_run.o: runner/main_run.c | $(B)/.deps
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) -DRPS3_MPI -Irunner $(GSL_CFLAGS) $(HDF5_CFLAGS) $(MPI_CFLAGS) $(WARN) $(OPT) -MMD -MP -c $< -o $@
$(B)/rps3-run-mpi: $(B)/runner-mpi/main_run.o $(RUN_OBJ) $(B)/librps3.a
	$(CC) -o $@ $^ $(HDF5_LIBS) $(YAML_LIBS) $(GSL_LIBS) $(MPI_LIBS) -lpthread -lm

# ------------------------------------------------------------------- tests
$(B)/tests/%: tests/%.c $(B)/librps3.a tests/testutil.h
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) -Itests $(GSL_CFLAGS) $(WARN) $(OPT) -g $< -o $@ \
	  $(B)/librps3.a $(CMOCKA_LIBS) $(GSL_LIBS)
$(B)/tests-san/%: tests/%.c $(B)/librps3-san.a tests/testutil.h
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) -Itests -DRPS3_SANITIZE $(GSL_CFLAGS) $(WARN) -O1 -g $(SAN) $< -o $@ \
	  $(B)/librps3-san.a $(CMOCKA_LIBS) $(GSL_LIBS)

check-c: $(TEST_BIN)
	@set -e; for t in $(TEST_BIN); do echo "== $$t"; $$t; done

check-san: $(TEST_SAN)
	@set -e; for t in $(TEST_SAN); do echo "== $$t (asan+ubsan)"; \
	  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 $$t; done

check-py: all venv
	$(VPY) -m pytest -q tests

# pytest last, so that a run ends on its summary line
check: lib runner check-c check-san valgrind check-fuzz check-py

# ------------------------------------------------------------------- bench
# rps3-bench (tests/bench/): per-call medians of every stage, a table on
# stdout and out/bench.h5.  -O2, no sanitizers; timings are never asserted.
BENCH_SRC = $(wildcard tests/bench/*.c)
$(B)/rps3-bench: $(BENCH_SRC) $(wildcard tests/bench/*.h) $(B)/librps3.a
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) $(GSL_CFLAGS) $(HDF5_CFLAGS) $(WARN) -O2 $(BENCH_SRC) \
	  -o $@ $(B)/librps3.a $(HDF5_LIBS) $(GSL_LIBS) -lm
# then tests/bench/runner_bench.py: rps3-run's points per second and peak
# RSS (GNU time) for sweeps of 10^3 to 10^7 points, -j 1 and 2, into
# out/bench_runner.h5.  About a minute; the 10^7-point files (3.2 GB) are
# written next to it and removed.
bench: $(B)/rps3-bench runner venv
	@mkdir -p out
	$(B)/rps3-bench -o out/bench.h5
	$(VPY) tests/bench/runner_bench.py -o out/bench_runner.h5

# ---------------------------------------------------------------- valgrind
# memcheck on the threads test and a short control loop: any error or leak
# fails.  About 10 s, so `make check` runs it.
VALGRIND = valgrind -q --error-exitcode=1 --leak-check=full \
           --errors-for-leak-kinds=definite,possible
.PHONY: valgrind
valgrind: $(B)/tests/test_threads $(B)/tests/example_control_loop
	$(VALGRIND) $(B)/tests/test_threads
	$(VALGRIND) $(B)/tests/example_control_loop 100

# -------------------------------------------------------------------- fuzz
# libFuzzer over the scene parser (tests/fuzz/fuzz_scene.c) with ASan and
# UBSan, seeded from configs/ and tests/bad_scenes/.  check-fuzz is a bounded
# 20 s run; the long run is in docs/hard-cases.md.
FUZZ_CC = clang
FUZZ_FLAGS = -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
FUZZ_TIME ?= 20
$(B)/fuzz_scene: tests/fuzz/fuzz_scene.c runner/scene.c runner/scene.h $(LIB_SRC) | $(B)/.deps
	@mkdir -p $(@D)
	$(FUZZ_CC) $(CPPFLAGS_ALL) -Irunner $(GSL_CFLAGS) $(WARN) $(FUZZ_FLAGS) \
	  tests/fuzz/fuzz_scene.c runner/scene.c $(LIB_SRC) -o $@ $(YAML_LIBS) $(GSL_LIBS) -lm
.PHONY: check-fuzz
check-fuzz: $(B)/fuzz_scene
	@mkdir -p $(B)/fuzz-corpus
	$(B)/fuzz_scene -max_total_time=$(FUZZ_TIME) -timeout=5 -rss_limit_mb=2048 \
	  -dict=tests/fuzz/scene.dict -print_final_stats=1 \
	  $(B)/fuzz-corpus configs tests/bad_scenes

# ------------------------------------------------------------------- study
# rps3-study (runner/main_study.c): what accuracy costs in time, and the
# workspace map, into out/*.h5; the figures and the table of recommended
# settings (out/accuracy_table.md) by analysis/.  About 20 s.
study-bin: $(B)/rps3-study
check-py: study-bin
study: study-bin venv
	@mkdir -p out
	$(B)/rps3-study accuracy -o out/accuracy.h5 --samples 1000 --repeats 21
	$(B)/rps3-study workspace -o out/workspace.h5
	$(VPY) analysis/accuracy_cost.py out/accuracy.h5 out > out/accuracy_table.md
	$(VPY) analysis/workspace.py out/workspace.h5 out

# ------------------------------------------------------------------- paper
paper: all venv
	@mkdir -p out
	$(B)/rps3-run configs/paper.yaml -o out/paper.h5
	$(B)/rps3-run configs/link_mass.yaml -o out/link_mass.h5
	$(VPY) analysis/figures.py out/paper.h5 out
	$(VPY) analysis/check_paper.py out/paper.h5 --sweep out/link_mass.h5

clean:
	rm -rf $(B) out

-include $(wildcard $(B)/obj/*.d $(B)/pic/*.d $(B)/san/*.d $(B)/runner/*.d \
                   $(B)/runner-mpi/*.d)
