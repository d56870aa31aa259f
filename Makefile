# rps3 - one plain Makefile.  `make paper` and `make check` are the two
# commands a new user needs; both install the Debian packages they need
# first (as root).  A plain `make` installs nothing: it says what is missing.

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
# libcrypto (OpenSSL): the SHA-256 of the files a scene reads (runner/scene/inputs.c)
CRYPTO_LIBS = $(shell pkg-config --libs libcrypto 2>/dev/null || echo -lcrypto)
MPI_CFLAGS = $(shell pkg-config --cflags ompi-c 2>/dev/null)
MPI_LIBS = $(shell pkg-config --libs ompi-c 2>/dev/null)
CMOCKA_LIBS = -lcmocka
SAN = -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
PYTHON ?= python3
VENV = .venv
VPY = $(VENV)/bin/python

# Debian packages: what the library and the runner need to build, what
# `make paper` adds (the Python package is compiled against rps3.h, so the
# Python headers), and what `make check` and `make bench` add (a second
# compiler and libFuzzer, cmocka, valgrind, MPI, GNU time, CMake for the
# install test)
DEB_BUILD = gcc make pkg-config libgsl-dev libhdf5-dev libyaml-dev zlib1g-dev libssl-dev
DEB_PAPER = $(DEB_BUILD) python3-venv python3-dev
DEB_CHECK = $(DEB_PAPER) clang libclang-rt-dev libcmocka-dev libopenmpi-dev openmpi-bin \
            valgrind time cmake strace
# rps3.view's tests: MP4 frames (ffmpeg, ffprobe) and the HTML page in a
# headless browser
DEB_CHECK += ffmpeg chromium

# version, from the header; the shared library's SONAME carries the major
VERSION := $(shell sed -n 's/^\#define RPS3_VERSION_STRING "\(.*\)"/\1/p' include/rps3.h)
SOVERSION := $(shell sed -n 's/^\#define RPS3_VERSION_MAJOR \([0-9]*\)/\1/p' include/rps3.h)

# installation (GNU conventions): `make install PREFIX=/usr/local`,
# DESTDIR for staged installs
PREFIX ?= /usr/local
BINDIR ?= $(PREFIX)/bin
LIBDIR ?= $(PREFIX)/lib
INCLUDEDIR ?= $(PREFIX)/include
PKGCONFIGDIR ?= $(LIBDIR)/pkgconfig
CMAKEDIR ?= $(LIBDIR)/cmake/rps3
INSTALL ?= install
INSTALL_PROGRAM ?= $(INSTALL) -m 755
INSTALL_DATA ?= $(INSTALL) -m 644

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
TEST_BIN += $(B)/tests/example_control_loop $(B)/tests/example_sim_loop
# the runner's subsystems, one folder each, lowest first: a folder uses only
# the ones before it (docs/runner.md; `make cycles` checks it)
RUN_DIRS = core scene output exec shards study bin
RUN_SRC = $(foreach d,$(RUN_DIRS),$(wildcard runner/$(d)/*.c))
# runner/mpi/ is the only code that knows MPI: rps3-run-mpi links
# world_mpi.c, every other program the one-process stub
WORLD_STUB = $(B)/runner/mpi/world_stub.o
WORLD_MPI = $(B)/runner-mpi/mpi/world_mpi.o
RUN_MAINS = runner/bin/main_run.c runner/bin/main_study.c runner/bin/main_simstudy.c
# the steps of a run (run_steps.c) that sweeps and design studies share
RUN_MAINS += runner/bin/run_steps.c runner/bin/run_ident.c
RUN_DESIGN_OBJ = $(B)/runner/bin/run_steps.o $(B)/runner/bin/run_ident.o
# rps3-study's own files (study.h); the rest is every program's
STUDY_SRC = $(wildcard runner/study/*.c)
STUDY_OBJ = $(STUDY_SRC:runner/%.c=$(B)/runner/%.o)
RUN_COMMON = $(filter-out $(RUN_MAINS) $(STUDY_SRC),$(RUN_SRC))
RUN_OBJ = $(RUN_COMMON:runner/%.c=$(B)/runner/%.o) $(B)/runner/gitrev.o

.PHONY: all lib runner runner-mpi study-bin check check-c check-san check-py check-lint check-slurm paper \
        study bench mutation scaling deps venv venv-check clean install uninstall

# the MPI runner is part of `all` when OpenMPI is there; `make check`
# builds it in any case
HAVE_MPI := $(shell pkg-config --exists ompi-c 2>/dev/null && echo 1)
all: lib runner $(if $(HAVE_MPI),runner-mpi)

# ------------------------------------------------------------ dependencies
# $(call deps_recipe,PACKAGES,INSTALL): the Debian packages of the list that
# are missing are installed when INSTALL is 1 and make runs as root;
# otherwise make stops with the exact command to run.
define deps_recipe
	@missing=""; for p in $(1); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" \
	    || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$(2)" = 1 ] && [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing Debian packages:$$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive \
	      apt-get install -y -qq --no-install-recommends $$missing >/dev/null || exit 1; \
	  else \
	    echo "missing Debian packages:$$missing"; \
	    echo "run:  sudo apt-get install -y$$missing"; \
	    [ "$(2)" = 1 ] || echo "(as root, make paper and make check install them)"; \
	    exit 1; \
	  fi; \
	fi
	@mkdir -p $(B) && touch $@
endef

# The set of packages is the one of the largest goal on the command line,
# known when the Makefile is read, so that a single stamp, made before
# anything compiles, checks (and for paper and check, installs) it all.
CHECK_GOALS = check check-c check-san check-py check-lint check-fuzz valgrind bench \
              mutation scaling
PAPER_GOALS = paper study venv venv-check design
ifneq ($(filter $(CHECK_GOALS),$(MAKECMDGOALS)),)
DEPS_SET = check
DEPS_PKGS = $(DEB_CHECK)
DEPS_INSTALL = 1
else ifneq ($(filter $(PAPER_GOALS),$(MAKECMDGOALS)),)
DEPS_SET = paper
DEPS_PKGS = $(DEB_PAPER)
DEPS_INSTALL = 1
else ifneq ($(filter runner-mpi,$(MAKECMDGOALS)),)
DEPS_SET = mpi
DEPS_PKGS = $(DEB_BUILD) libopenmpi-dev openmpi-bin
DEPS_INSTALL = 0
else
DEPS_SET = build
DEPS_PKGS = $(DEB_BUILD)
DEPS_INSTALL = 0
endif
DEPS = $(B)/.deps-$(DEPS_SET)
deps: $(DEPS)
$(DEPS):
	$(call deps_recipe,$(DEPS_PKGS),$(DEPS_INSTALL))

# the venv: analysis/requirements.txt (what the figures need, and the
# package's build), then the rps3 package from python/ (compiled against
# include/rps3.h, librps3-pic.a linked in), reinstalled whenever the
# package, the header or the library changes.  venv-check adds the test
# and benchmark tools of tests/requirements.txt and the optimisers of
# analysis/requirements-design.txt, for the targets that use them
# (check-py, check-lint, bench, mutation, ...), so that `make paper`
# installs only the first.
PY_PKG = python/pyproject.toml python/setup.py $(wildcard python/rps3/*.py)
venv: $(VENV)/.ok $(VENV)/.rps3
venv-check: venv $(VENV)/.check
$(VENV)/.ok: analysis/requirements.txt | $(DEPS)
	$(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install -q --disable-pip-version-check -r analysis/requirements.txt
	@touch $@
$(VENV)/.check: tests/requirements.txt analysis/requirements-design.txt $(VENV)/.ok
	$(VPY) -m pip install -q --disable-pip-version-check -r tests/requirements.txt \
	  -r analysis/requirements-design.txt
	@touch $@
$(VENV)/.rps3: $(PY_PKG) include/rps3.h $(B)/librps3-pic.a $(VENV)/.ok
	$(VPY) -m pip install -q --disable-pip-version-check --no-deps \
	  --no-build-isolation --force-reinstall ./python
	@touch $@

# ------------------------------------------------------- compiler and flags
# Every object depends on a stamp holding the compiler (its name and its
# --version line) and the flags: `make CC=clang` after a gcc build, or a
# changed OPT, rebuilds everything; an unchanged stamp keeps its time, so
# that nothing rebuilds otherwise.
FLAGS_STAMP = $(B)/.flags
BUILD_FLAGS = CC=$(CC) [$(shell $(CC) --version 2>/dev/null | head -n 1)] \
  OPT=$(OPT) WARN=$(WARN) CPPFLAGS=$(CPPFLAGS_ALL) GSL=$(GSL_CFLAGS) \
  HDF5=$(HDF5_CFLAGS) MPI=$(MPI_CFLAGS) SAN=$(SAN) KERNEL=$(KERNEL_FLAGS) \
  SIM=$(SIM_FLAGS)
$(FLAGS_STAMP): FORCE
	@mkdir -p $(@D)
	@printf '%s\n' '$(BUILD_FLAGS)' > $@.new
	@if cmp -s $@.new $@; then rm $@.new; else mv $@.new $@; fi

# ----------------------------------------------------------------- library
# librps3.so is a link to librps3.so.SOVERSION (the SONAME), itself a link
# to the file librps3.so.VERSION, as installed
SO_REAL = librps3.so.$(VERSION)
SO_NAME = librps3.so.$(SOVERSION)
lib: $(B)/librps3.a $(B)/librps3.so $(B)/librps3-pic.a

# the batch kernel (src/batch_kernel.c) is a `#pragma omp simd` loop:
# vectorised without errno or trapping maths (which would keep the selects
# of the loop body branches) and without contraction into FMA, so that every
# vector width gives the same results (docs/performance.md)
KERNEL_FLAGS = -fopenmp-simd -fno-math-errno -fno-trapping-math -ffp-contract=off
$(B)/obj/batch_kernel.o $(B)/pic/batch_kernel.o $(B)/san/batch_kernel.o: XFLAGS = $(KERNEL_FLAGS)
# the simulation's per-evaluation path (forward dynamics, the integrator's
# stages, the controllers and their desired motion, the theta solve) is
# loops of three:
# unrolled, they take a third fewer instructions (docs/simulation.md);
# unrolling does not reorder any arithmetic, so the results are the same
# bits
SIM_FLAGS = -funroll-loops -fno-math-errno
$(foreach f,fk theta_gsl fwddyn fwddyn_theta fwddyn_shared fwddyn_body fwddyn_singular sim sim_measure control velocity,$(B)/obj/$(f).o $(B)/pic/$(f).o): XFLAGS = $(SIM_FLAGS)
# the design's per-pose path: the 6x6 LU and inverse with their loops
# unrolled (the same operations in the same order), 14 % fewer instructions
$(foreach f,linalg design design_eval design_task,$(B)/obj/$(f).o $(B)/pic/$(f).o): XFLAGS = -funroll-loops

$(B)/obj/%.o: src/%.c $(FLAGS_STAMP) | $(DEPS)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) $(GSL_CFLAGS) $(WARN) $(OPT) $(XFLAGS) -MMD -MP -c $< -o $@
$(B)/pic/%.o: src/%.c $(FLAGS_STAMP) | $(DEPS)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) $(GSL_CFLAGS) $(WARN) $(OPT) $(XFLAGS) -fPIC -fvisibility=hidden -MMD -MP -c $< -o $@
$(B)/san/%.o: src/%.c $(FLAGS_STAMP) | $(DEPS)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) $(GSL_CFLAGS) $(WARN) -O1 -g $(SAN) $(XFLAGS) -MMD -MP -c $< -o $@

$(B)/librps3.a: $(LIB_OBJ)
	ar rcs $@ $^
$(B)/$(SO_REAL): $(LIB_PIC)
	$(CC) -shared -Wl,-soname,$(SO_NAME) -o $@ $^ $(GSL_LIBS)
$(B)/$(SO_NAME): $(B)/$(SO_REAL)
	ln -sf $(SO_REAL) $@
$(B)/librps3.so: $(B)/$(SO_NAME)
	ln -sf $(SO_NAME) $@
# the shared library's objects (-fPIC) as an archive, which the Python
# extension links in (python/rps3/_build.py): same code, same results
$(B)/librps3-pic.a: $(LIB_PIC)
	ar rcs $@ $^
$(B)/librps3-san.a: $(LIB_SAN)
	ar rcs $@ $^

# ------------------------------------------------------------------ runner
# the three programs: a rebuilt library never leaves a stale rps3-study or
# rps3-simstudy beside a fresh rps3-run
runner: $(B)/rps3-run $(B)/rps3-study $(B)/rps3-simstudy

$(B)/runner/%.o: runner/%.c $(FLAGS_STAMP) | $(DEPS)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) -Irunner $(GSL_CFLAGS) $(HDF5_CFLAGS) $(WARN) $(OPT) -MMD -MP -c $< -o $@
# the git revision the runner is built from, for the files' history and
# git_revision attributes: the source is rewritten only when the revision
# changes, so that nothing rebuilds otherwise ("unknown" without git)
GIT_REV := $(shell git describe --always --dirty --abbrev=12 2>/dev/null || echo unknown)
$(B)/runner/gitrev.c: FORCE
	@mkdir -p $(@D)
	@echo 'const char *const rps3_git_revision = "$(GIT_REV)";' > $@.new
	@if cmp -s $@.new $@; then rm $@.new; else mv $@.new $@; fi
$(B)/runner/gitrev.o: $(B)/runner/gitrev.c $(FLAGS_STAMP)
	$(CC) $(WARN) $(OPT) -c $< -o $@
FORCE:
$(B)/rps3-run: $(B)/runner/bin/main_run.o $(RUN_DESIGN_OBJ) $(RUN_OBJ) $(WORLD_STUB) $(B)/librps3.a
	$(CC) -o $@ $^ $(HDF5_LIBS) $(YAML_LIBS) $(GSL_LIBS) $(CRYPTO_LIBS) -lz -lpthread -lm
$(B)/rps3-study: $(B)/runner/bin/main_study.o $(STUDY_OBJ) $(RUN_OBJ) $(B)/librps3.a
	$(CC) -o $@ $^ $(HDF5_LIBS) $(YAML_LIBS) $(GSL_LIBS) $(CRYPTO_LIBS) -lz -lpthread -lm
# rps3-simstudy (runner/bin/main_simstudy.c): closed-loop tracking and what
# simulation accuracy costs in time; `make simulation` runs it
$(B)/rps3-simstudy: $(B)/runner/bin/main_simstudy.o $(STUDY_OBJ) $(RUN_OBJ) $(B)/librps3.a
	$(CC) -o $@ $^ $(HDF5_LIBS) $(YAML_LIBS) $(GSL_LIBS) $(CRYPTO_LIBS) -lz -lpthread -lm

# rps3-run-mpi: the same program linked with runner/mpi/world_mpi.c, for
# `mpirun -n N build/rps3-run-mpi SCENE.yaml -o OUT.h5` (Debian's OpenMPI)
runner-mpi: $(B)/rps3-run-mpi
$(WORLD_MPI): runner/mpi/world_mpi.c $(FLAGS_STAMP) | $(DEPS)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) -Irunner $(MPI_CFLAGS) $(WARN) $(OPT) -MMD -MP -c $< -o $@
$(B)/rps3-run-mpi: $(B)/runner/bin/main_run.o $(RUN_DESIGN_OBJ) $(RUN_OBJ) $(WORLD_MPI) $(B)/librps3.a
	$(CC) -o $@ $^ $(HDF5_LIBS) $(YAML_LIBS) $(GSL_LIBS) $(MPI_LIBS) $(CRYPTO_LIBS) -lz -lpthread -lm

# ------------------------------------------------------------------- tests
$(B)/tests/%: tests/%.c $(B)/librps3.a tests/testutil.h tests/alloc_count.h $(FLAGS_STAMP) | $(DEPS)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) -Itests $(GSL_CFLAGS) $(WARN) $(OPT) -g $< -o $@ \
	  $(B)/librps3.a $(CMOCKA_LIBS) $(GSL_LIBS)
# test_pool compiles the runner's worker pool in
$(B)/tests/test_pool $(B)/tests-san/test_pool: runner/exec/pool.c runner/exec/pool.h
$(B)/tests-san/%: tests/%.c $(B)/librps3-san.a tests/testutil.h tests/alloc_count.h $(FLAGS_STAMP) | $(DEPS)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) -Itests -DRPS3_SANITIZE $(GSL_CFLAGS) $(WARN) -O1 -g $(SAN) $< -o $@ \
	  $(B)/librps3-san.a $(CMOCKA_LIBS) $(GSL_LIBS)

check-c: $(TEST_BIN)
	@set -e; for t in $(TEST_BIN); do echo "== $$t"; $$t; done

check-san: $(TEST_SAN)
	@set -e; for t in $(TEST_SAN); do echo "== $$t (asan+ubsan)"; \
	  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 $$t; done

check-py: all runner-mpi venv-check
	$(VPY) -m pytest -q tests

# the runner's files without a circle, each folder using only the ones
# below it (scripts/check_cycles.py, docs/runner.md "Code layout"): the
# sources' includes and the symbols their objects define and use
.PHONY: cycles
cycles: runner $(if $(HAVE_MPI),runner-mpi)
	$(PYTHON) scripts/check_cycles.py --root runner --objects $(B)/runner \
	  $(if $(HAVE_MPI),--objects $(B)/runner-mpi)

# ruff and mypy over the Python package and the analysis scripts
check-lint: venv-check
	$(VPY) -m ruff check --config python/pyproject.toml python analysis
	$(VPY) -m mypy --config-file python/pyproject.toml python/rps3 analysis

# pytest last, so that a run ends on its summary line
check: lib runner check-c check-san valgrind check-fuzz check-lint cycles check-py

# ------------------------------------------------------------- check-slurm
# The shipped Slurm scripts (scripts/slurm/) under a single-node Slurm on
# localhost, every output compared with a single-process run
# (tests/slurm/check_slurm.sh; docs/scale-out.md).  As root on Debian it
# installs slurm-wlm and munge and starts and stops its own daemons;
# otherwise it says why it skips.  Not part of `make check`.
check-slurm: all venv-check
	tests/slurm/check_slurm.sh

# ------------------------------------------------------------------- bench
# rps3-bench (tests/bench/): per-call medians of every stage, a table on
# stdout and out/bench.h5.  -O2, no sanitizers; timings are never asserted.
# Its anchor is C generated at build time by tests/bench/gen_anchor.py
# (SymPy: the paper's model in pose coordinates, cse, ccode) into
# $(B)/anchor/; anchor-check (run by check-py) holds it to the library.
# The batched anchor (the same program in a loop over structures of arrays,
# generated beside it) is compiled as the library's batch kernel is: its
# flags and target clones, so that the compiler vectorises it alike.
# With glibc's libmvec (when -lmvec links), its vector sin and cos too.
ANCHOR = $(B)/anchor/anchor_gen.c
ANCHOR_BATCH = $(B)/anchor/anchor_gen_batch.o
ANCHOR_MVEC = $(shell printf 'int main(void) { return 0; }\n' | \
  $(CC) -x c - -lmvec -o /dev/null 2>/dev/null && echo 1)
ANCHOR_LIBS = $(if $(ANCHOR_MVEC),-lmvec) -lm
$(ANCHOR): tests/bench/gen_anchor.py | $(VENV)/.check
	$(VPY) tests/bench/gen_anchor.py -o $@
$(B)/anchor/anchor_gen_batch.c: $(ANCHOR) ;
$(ANCHOR_BATCH): $(B)/anchor/anchor_gen_batch.c $(FLAGS_STAMP)
	$(CC) $(CPPFLAGS_ALL) $(WARN) -O2 $(KERNEL_FLAGS) \
	  $(if $(ANCHOR_MVEC),-DRPS3_ANCHOR_LIBMVEC -fno-builtin-sin -fno-builtin-cos) -c $< -o $@
$(B)/anchor-check: tests/bench/anchor_check.c $(ANCHOR) $(ANCHOR_BATCH) $(B)/librps3.a
	$(CC) $(CPPFLAGS_ALL) -I$(B)/anchor $(GSL_CFLAGS) $(WARN) -O2 $< $(ANCHOR) \
	  $(ANCHOR_BATCH) -o $@ $(B)/librps3.a $(GSL_LIBS) $(ANCHOR_LIBS)
check-py: $(B)/anchor-check
BENCH_SRC = tests/bench/bench.c tests/bench/bench_h5.c
$(B)/rps3-bench: $(BENCH_SRC) $(wildcard tests/bench/*.h) $(ANCHOR) $(ANCHOR_BATCH) $(B)/librps3.a
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS_ALL) -I$(B)/anchor $(GSL_CFLAGS) $(HDF5_CFLAGS) $(WARN) -O2 \
	  $(BENCH_SRC) $(ANCHOR) $(ANCHOR_BATCH) -o $@ $(B)/librps3.a $(HDF5_LIBS) $(GSL_LIBS) \
	  $(ANCHOR_LIBS)
# rps3-mujoco-bench (tests/bench/mujoco_bench.c): MuJoCo's mj_inverse on the
# same states, from the C library of the pinned `mujoco` wheel in .venv
MUJOCO_DIR = $(shell $(VPY) -c 'import mujoco, os; print(os.path.dirname(mujoco.__file__))' 2>/dev/null)
$(B)/rps3-mujoco-bench: tests/bench/mujoco_bench.c $(ANCHOR) $(B)/librps3.a | $(VENV)/.check
	$(CC) $(CPPFLAGS_ALL) -I$(B)/anchor -isystem $(MUJOCO_DIR)/include $(GSL_CFLAGS) $(WARN) -O2 \
	  $< $(ANCHOR) -o $@ $(B)/librps3.a $(firstword $(wildcard $(MUJOCO_DIR)/libmujoco.so.*)) \
	  -Wl,-rpath,$(MUJOCO_DIR) $(GSL_LIBS) -lm
# then tests/bench/python_bench.py: the Python package against the C
# batch call it wraps, 10^6 points in one process; and
# tests/bench/runner_bench.py: rps3-run's points per second and peak
# RSS (GNU time) for sweeps of 10^3 to 10^7 points, -j 1 and 2, into
# out/bench_runner.h5.  About a minute; the 10^7-point files (3.2 GB) are
# written next to it and removed.
bench: $(B)/rps3-bench $(B)/rps3-mujoco-bench runner venv-check
	@mkdir -p out
	$(B)/rps3-bench -o out/bench.h5
	@grep -m1 "model name" /proc/cpuinfo || true
	$(B)/rps3-mujoco-bench
	$(VPY) tests/bench/runner_bench.py -o out/bench_runner.h5
	$(VPY) tests/bench/python_bench.py

# ----------------------------------------------------------------- scaling
# one compute-bound sweep (3 M points) by -j 1, -j 2, an array of 2 shards
# + merge and mpirun -n 2: wall, CPU, speed-up, efficiency, medians of 3
# (tests/bench/scaling.py; the table in docs/scale-out.md).  A few minutes.
scaling: runner runner-mpi venv-check
	$(VPY) tests/bench/scaling.py

# what a design study costs in rps3-run, and the 10^5 x 10^3 target from it
# (docs/runner.md, "Design studies")
.PHONY: bench-design
bench-design: runner venv
	$(VPY) tests/bench/design_bench.py

# ---------------------------------------------------------------- mutation
# which test kills which hand-made mutation of src/ (tests/mutation.py, in a
# temporary copy of the tree): writes docs/mutations.md, exits 1 when a
# mutation survives.  Each mutation's tests run until the first kill, the
# one docs/mutations.md names first; not part of `check`.
mutation: venv-check
	nice $(VPY) tests/mutation.py -o docs/mutations.md

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
# the scene parser's sources: the fuzz target links these and the library
FUZZ_SCENE_SRC = runner/scene/scene.c runner/scene/scene_load.c runner/scene/scene_parse.c \
  runner/scene/scene_sweep.c \
  runner/scene/scene_case.c runner/scene/scene_emit.c \
  runner/scene/table.c runner/scene/table_read.c \
  runner/scene/table_h5.c runner/scene/design.c runner/scene/identify.c runner/core/hint.c runner/core/h5err.c \
  runner/core/safeio.c
FUZZ_SCENE_SRC += runner/scene/scene_bodies.c
$(B)/fuzz_scene: tests/fuzz/fuzz_scene.c $(FUZZ_SCENE_SRC) $(wildcard runner/scene/*.h) runner/core/hint.h runner/core/h5err.h runner/core/safeio.h $(LIB_SRC) | $(DEPS)
	@mkdir -p $(@D)
	$(FUZZ_CC) $(CPPFLAGS_ALL) -Irunner $(GSL_CFLAGS) $(HDF5_CFLAGS) $(WARN) $(FUZZ_FLAGS) $(KERNEL_FLAGS) \
	  tests/fuzz/fuzz_scene.c $(FUZZ_SCENE_SRC) $(LIB_SRC) -o $@ $(YAML_LIBS) $(HDF5_LIBS) $(GSL_LIBS) -lm
.PHONY: check-fuzz
check-fuzz: $(B)/fuzz_scene
	@mkdir -p $(B)/fuzz-corpus
	$(B)/fuzz_scene -max_total_time=$(FUZZ_TIME) -timeout=5 -rss_limit_mb=2048 \
	  -dict=tests/fuzz/scene.dict -print_final_stats=1 \
	  $(B)/fuzz-corpus configs tests/bad_scenes

# ------------------------------------------------------------------- study
# rps3-study (runner/bin/main_study.c): what accuracy costs in time, and the
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
	$(VPY) analysis/assembly_modes.py out

# the figure of docs/assembly-modes.md alone (numpy, a few seconds)
.PHONY: assembly-modes
assembly-modes: venv
	@mkdir -p out
	$(VPY) analysis/assembly_modes.py out

# -------------------------------------------------------------- simulation
# closed-loop tracking (PD, PD + gravity, computed torque; exact model and
# no link mass; helix and fast sine) and what simulation accuracy costs:
# out/simstudy.h5, the figures out/tracking_*.png and
# out/simulation_accuracy.png, the tables in out/simulation_table.md.
# About 10 s (docs/simulation.md).
.PHONY: simulation
check-py: $(B)/rps3-simstudy
simulation: $(B)/rps3-simstudy venv
	@mkdir -p out
	$(B)/rps3-simstudy -o out/simstudy.h5
	$(VPY) analysis/simulation.py out/simstudy.h5 out > out/simulation_table.md
	@cat out/simulation_table.md

# configs/closed_loop.yaml simulated by rps3-run (out/closed_loop.h5) and
# drawn by analysis/closed_loop.py: out/closed_loop.png and its table in
# out/closed_loop.md (docs/simulation.md).  About a second.
.PHONY: closed-loop
closed-loop: $(B)/rps3-run venv
	@mkdir -p out
	$(B)/rps3-run configs/closed_loop.yaml -o out/closed_loop.h5 -q
	$(VPY) analysis/closed_loop.py out/closed_loop.h5 out/closed_loop.png > out/closed_loop.md
	@cat out/closed_loop.md

# ------------------------------------------------------------------ design
# The design optimisation (docs/design-optimisation.md): the performance
# atlas, the Pareto fronts of NSGA-II over 5 seeds with their
# hypervolumes, NLopt's constrained optimum against a dense grid, and the
# chosen design beside Table II's, by analysis/design.py into out/design/
# (figures and design.md, the numbers of the page).  A few minutes.
.PHONY: design
DESIGN_REQ = analysis/requirements-design.txt
$(VENV)/.design: $(DESIGN_REQ) $(VENV)/.ok
	$(VPY) -m pip install -q --disable-pip-version-check -r $(DESIGN_REQ)
	@touch $@
design: venv $(VENV)/.design
	@mkdir -p out/design
	nice $(VPY) analysis/design.py -o out/design

# ------------------------------------------------------------------- paper
paper: all venv
	@mkdir -p out
	$(B)/rps3-run configs/paper.yaml -o out/paper.h5
	$(B)/rps3-run configs/link_mass.yaml -o out/link_mass.h5
	$(VPY) analysis/figures.py out/paper.h5 out
	$(VPY) analysis/check_paper.py out/paper.h5 --sweep out/link_mass.h5

# --------------------------------------------------------------- man pages
# One page a program, made from its own --help and --version
# (packaging/man1.awk), so that a page lists exactly the option table the
# program parses; rps3-run-mpi parses rps3-run's table.  `make install`
# puts them into $(MANDIR)/man1.
MAN_PROGS = rps3-run rps3-study rps3-simstudy rps3-run-mpi
.PHONY: man
man: $(MAN_PROGS:%=$(B)/man/%.1)
$(B)/man/%.1: $(B)/% packaging/man1.awk
	@mkdir -p $(@D)
	$< --help > $@.help
	$< --version > $@.version
	awk -v prog=$* -f packaging/man1.awk $@.help $@.version > $@
	@rm -f $@.help $@.version
MPI_MAN_NOTE = rps3-run-mpi is rps3-run built with MPI (make runner-mpi): under mpirun -n N each rank computes one shard and rank 0 joins the parts into OUT.h5 (docs/scale-out.md).
$(B)/man/rps3-run-mpi.1: $(B)/rps3-run packaging/man1.awk
	@mkdir -p $(@D)
	$< --help > $@.help
	$< --version > $@.version
	awk -v prog=rps3-run-mpi -v note="$(MPI_MAN_NOTE)" \
	  -f packaging/man1.awk $@.help $@.version > $@
	@rm -f $@.help $@.version

# ----------------------------------------------------------------- install
# `make install PREFIX=/usr/local` (as root), or a staged install with
# DESTDIR=/tmp/stage.  Installs the shared library with its SONAME links,
# the static library, the header, the runner programs, a pkg-config file
# (pkg-config --cflags --libs rps3) and a CMake package (find_package(rps3),
# target rps3::rps3).  ldconfig runs for a direct install as root.
DOCDIR ?= $(PREFIX)/share/doc/rps3
MANDIR ?= $(PREFIX)/share/man
INSTALL_BINS = rps3-run rps3-study rps3-simstudy $(if $(HAVE_MPI),rps3-run-mpi)
install: lib runner study-bin $(if $(HAVE_MPI),runner-mpi) $(INSTALL_BINS:%=$(B)/man/%.1)
	@case "$(PREFIX)" in /*) ;; *) echo "PREFIX must be an absolute path: $(PREFIX)"; exit 1;; esac
	$(INSTALL) -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(INCLUDEDIR) \
	  $(DESTDIR)$(PKGCONFIGDIR) $(DESTDIR)$(CMAKEDIR) $(DESTDIR)$(DOCDIR) \
	  $(DESTDIR)$(MANDIR)/man1
	$(INSTALL_DATA) $(B)/$(SO_REAL) $(DESTDIR)$(LIBDIR)/$(SO_REAL)
	ln -sf $(SO_REAL) $(DESTDIR)$(LIBDIR)/$(SO_NAME)
	ln -sf $(SO_NAME) $(DESTDIR)$(LIBDIR)/librps3.so
	$(INSTALL_DATA) $(B)/librps3.a $(DESTDIR)$(LIBDIR)/librps3.a
	$(INSTALL_DATA) include/rps3.h $(DESTDIR)$(INCLUDEDIR)/rps3.h
	for p in $(INSTALL_BINS); do $(INSTALL_PROGRAM) $(B)/$$p $(DESTDIR)$(BINDIR)/$$p || exit 1; \
	  $(INSTALL_DATA) $(B)/man/$$p.1 $(DESTDIR)$(MANDIR)/man1/$$p.1 || exit 1; done
	$(INSTALL_DATA) LICENSE CITATION.cff $(DESTDIR)$(DOCDIR)/
	sed -e 's|@PREFIX@|$(PREFIX)|' -e 's|@LIBDIR@|$(LIBDIR)|' \
	  -e 's|@INCLUDEDIR@|$(INCLUDEDIR)|' -e 's|@VERSION@|$(VERSION)|' \
	  packaging/rps3.pc.in > $(DESTDIR)$(PKGCONFIGDIR)/rps3.pc
	sed -e "s|@LIBDIR_FROM_CMAKEDIR@|$$(realpath -m --relative-to=$(CMAKEDIR) $(LIBDIR))|" \
	  -e "s|@INCLUDEDIR_FROM_LIBDIR@|$$(realpath -m --relative-to=$(LIBDIR) $(INCLUDEDIR))|" \
	  -e 's|@VERSION@|$(VERSION)|' -e 's|@SOVERSION@|$(SOVERSION)|' \
	  packaging/rps3-config.cmake.in > $(DESTDIR)$(CMAKEDIR)/rps3-config.cmake
	sed -e 's|@VERSION@|$(VERSION)|' -e 's|@SOVERSION@|$(SOVERSION)|' \
	  -e "s|@SIZEOF_VOID_P@|$$(echo __SIZEOF_POINTER__ | $(CC) -E -P - | tail -n 1)|" \
	  packaging/rps3-config-version.cmake.in > $(DESTDIR)$(CMAKEDIR)/rps3-config-version.cmake
	@if [ -z "$(DESTDIR)" ] && [ "$$(id -u)" = 0 ] && [ -x /sbin/ldconfig ]; then /sbin/ldconfig; fi

uninstall:
	rm -f $(DESTDIR)$(LIBDIR)/$(SO_REAL) $(DESTDIR)$(LIBDIR)/$(SO_NAME) \
	  $(DESTDIR)$(LIBDIR)/librps3.so $(DESTDIR)$(LIBDIR)/librps3.a \
	  $(DESTDIR)$(INCLUDEDIR)/rps3.h $(DESTDIR)$(PKGCONFIGDIR)/rps3.pc \
	  $(DESTDIR)$(CMAKEDIR)/rps3-config.cmake $(DESTDIR)$(CMAKEDIR)/rps3-config-version.cmake \
	  $(DESTDIR)$(DOCDIR)/LICENSE $(DESTDIR)$(DOCDIR)/CITATION.cff \
	  $(foreach p,$(MAN_PROGS),$(DESTDIR)$(BINDIR)/$(p) $(DESTDIR)$(MANDIR)/man1/$(p).1)
	-rmdir $(DESTDIR)$(CMAKEDIR) $(DESTDIR)$(DOCDIR) 2>/dev/null
	@if [ -z "$(DESTDIR)" ] && [ "$$(id -u)" = 0 ] && [ -x /sbin/ldconfig ]; then /sbin/ldconfig; fi

# ------------------------------------------------------------ trajectories
# the trajectory kinds waypoints, path and table (docs/trajectories.md): the
# shipped configs run, and one figure each in out/traj_*.png; the measured
# motion's forces against those of the smooth motion it samples in
# out/measured.png (configs/measured.csv is `analysis/measured.py generate`)
TRAJ_CONFIGS = pick_place circle line paper_path measured path_table
.PHONY: trajectories
trajectories: runner venv
	@mkdir -p out
	for c in $(TRAJ_CONFIGS); do $(B)/rps3-run configs/$$c.yaml -o out/$$c.h5 -q || exit 1; done
	$(VPY) analysis/trajectories.py out $(TRAJ_CONFIGS:%=out/%.h5)
	$(VPY) analysis/measured.py figure out/measured.h5 out

# the identification study (docs/identification.md): an optimised
# excitation, a simulated run, 200 fits with measured and 200 with
# differentiated states; out/ident_study.txt and out/ident_excitation.png
.PHONY: ident
ident: venv-check
	@mkdir -p out
	$(VPY) -m rps3.ident study --runs 200 --out out

# the identification Monte Carlo through the runner (docs/identification.md,
# "Through the runner"): 1000 draws of 1 % force noise on 10 s of an
# exciting trajectory at 1 kHz, each fitted by WLS and the consistent fit
# with 20 % of the samples held out, on 2 threads; the summary in
# out/ident_mc.txt, the draws in out/ident_mc.h5; then the general model's
# (configs/ident_general_mc.yaml, 1000 draws at 1 kHz on its own exciting
# table, about 4 min) into out/ident_general_mc.txt and .h5.  Not part
# of `make check` (tests/test_ident_runner.py runs 200 draws of a shorter
# trajectory and 20 with the consistent fit, tests/test_ident_runner_general.py
# 40 and 16 of the general model)
.PHONY: ident-mc
ident-mc: $(B)/rps3-run
	@mkdir -p out
	@start=$$(date +%s); \
	$(B)/rps3-run configs/ident_mc.yaml -o out/ident_mc.h5 -j 2 > out/ident_mc.txt && \
	echo "run time: $$(( $$(date +%s) - start )) s (-j 2)" >> out/ident_mc.txt; \
	status=$$?; cat out/ident_mc.txt; [ $$status -eq 0 ] || exit $$status; \
	start=$$(date +%s); \
	$(B)/rps3-run configs/ident_general_mc.yaml -o out/ident_general_mc.h5 -j 2 > out/ident_general_mc.txt && \
	echo "run time: $$(( $$(date +%s) - start )) s (-j 2)" >> out/ident_general_mc.txt; \
	status=$$?; cat out/ident_general_mc.txt; exit $$status

# the exciting trajectories of two general layouts (docs/identification.md,
# "A general layout"): rps3.ident_paper.design's defaults, seeds 1-5 of each
# against random Fourier series; the table in out/ident_excite.md (exit 1
# when a design misses the factor 5).  One BLAS thread: the matrices are
# small, and the times are per core
.PHONY: ident-excite
ident-excite: venv-check
	@mkdir -p out
	OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 $(VPY) analysis/ident_excite.py --out out/ident_excite.md

# ------------------------------------------------------------------- docs
# the key table of docs/runner.md is `rps3-run --keys`, its table of a
# simulated scene's datasets `rps3-run --sim-schema`; tests/test_docs.py
# fails when they differ
.PHONY: docs
docs: $(B)/rps3-run
	$(B)/rps3-run --keys > $(B)/keys.md
	awk 'FNR == NR { t = t $$0 "\n"; next } \
	     /^\| key \| type/ { printf "%s", t; skip = 1; next } \
	     skip && /^\|/ { next } { skip = 0; print }' \
	  $(B)/keys.md docs/runner.md > $(B)/runner.md.new
	$(B)/rps3-run --sim-schema > $(B)/sim_schema.md
	awk 'FNR == NR { t = t $$0 "\n"; next } \
	     /^\| dataset \| dimensions/ { printf "%s", t; skip = 1; next } \
	     skip && /^\|/ { next } { skip = 0; print }' \
	  $(B)/sim_schema.md $(B)/runner.md.new > $(B)/runner.md.new2
	$(B)/rps3-run --design-schema > $(B)/design_schema.md
	awk 'FNR == NR { t = t $$0 "\n"; next } \
	     /^\| design variable \| dimensions/ { printf "%s", t; skip = 1; next } \
	     skip && /^\|/ { next } { skip = 0; print }' \
	  $(B)/design_schema.md $(B)/runner.md.new2 > $(B)/runner.md.new3
	mv $(B)/runner.md.new3 docs/runner.md
	rm -f $(B)/runner.md.new2
	rm -f $(B)/runner.md.new

clean:
	rm -rf $(B) out python/build python/dist python/rps3.egg-info python/rps3/_rps3.*

-include $(wildcard $(B)/obj/*.d $(B)/pic/*.d $(B)/san/*.d $(B)/runner/*/*.d \
                   $(B)/runner-mpi/*/*.d)
