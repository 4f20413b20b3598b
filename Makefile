# Cascade build.  `make` builds bin/cascade-solver and bin/cascade.
#
#   make                 default build (-O2 -g) into bin/
#   make BUILD=release   -O3 -march=native into build/release/bin/
#   make SANITIZE=1      AddressSanitizer + UBSan into build/asan/bin/
#   make WERROR=1        warnings are errors (CI sets this)
#   make test | demo | bench | nightly | install PREFIX=... | clean | deps
#   make test-browser    the nightly dashboard in headless Chromium (installs chromium)
#   make soak [SOAK_JOBS=N SOAK_KILLS=N SOAK_RUNNERS=N SOAK_SECONDS=S]   runner soak test
#   make fuzz FUZZ_SECONDS=N   libFuzzer on every input reader (docs/fuzzing.md)
#
# Objects of each variant live under build/<variant>/ so switching variants
# never mixes objects compiled with different flags.

BUILD    ?= debug
SANITIZE ?= 0
WERROR   ?= 0
PREFIX   ?= /usr/local
JOBS     ?= $(shell nproc 2>/dev/null || echo 2)

CC       := mpicc
FUZZ_CLANG ?= clang
VERSION  := 0.1.0

ifeq ($(SANITIZE),1)
  VARIANT := asan
else ifeq ($(BUILD),release)
  VARIANT := release
else ifeq ($(BUILD),fuzz)
  VARIANT := fuzz
else
  VARIANT := debug
endif

ifeq ($(VARIANT),debug)
  BINDIR := bin
else
  BINDIR := build/$(VARIANT)/bin
endif
OBJDIR := build/$(VARIANT)/obj

OPT_debug   := -O2 -g
OPT_release := -O3 -march=native -g
# float-cast-overflow (a NaN or out-of-range double converted to an integer)
# is not part of gcc's "undefined" group: asked for by name
OPT_asan    := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined,float-cast-overflow \
               -fno-sanitize-recover=undefined,float-cast-overflow
# libFuzzer build (make fuzz): clang under mpicc, coverage instrumentation,
# ASan + UBSan; the harnesses get their LLVMFuzzerTestOneInput
OPT_fuzz    := -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined \
               -fno-sanitize-recover=undefined -DCASCADE_LIBFUZZER
ifeq ($(VARIANT),fuzz)
  CC := OMPI_CC=$(FUZZ_CLANG) mpicc
endif

PKGS     := hdf5-openmpi jansson yaml-0.1 gsl sqlite3 nettle
PKG_CFLAGS := $(shell pkg-config --cflags $(PKGS) 2>/dev/null)
PKG_LIBS   := $(shell pkg-config --libs $(PKGS) 2>/dev/null)
# Libraries are linked from the static archives of their -dev packages
# when those are installed (Debian ships them): the shared libhdf5 needs
# libcurl and libcrypto (its S3 driver, which Cascade never uses), and
# loading them with their own dependencies (GnuTLS, Kerberos, LDAP, ...)
# costs every process about 6 MiB of resident memory, the shared GSL,
# SQLite, Nettle, Jansson and libyaml 1.4 MiB more; from an archive only
# the objects Cascade calls are linked.  MPI, OpenMP and the C library
# stay shared.  STATIC_DEPS=0 links the shared libraries.
STATIC_DEPS ?= 1
HDF5_LIBDIR := $(patsubst -L%,%,$(firstword $(shell pkg-config --libs-only-L hdf5-openmpi 2>/dev/null)))
DEP_LIBDIRS := $(HDF5_LIBDIR) $(shell pkg-config --variable=libdir jansson 2>/dev/null)
archive_of = $(firstword $(wildcard $(addsuffix /lib$(1).a,$(DEP_LIBDIRS))))
STATIC_CANDIDATES := -lhdf5 -ljansson -lyaml -lgsl -lgslcblas -lsqlite3 -lnettle
ifeq ($(STATIC_DEPS),1)
  HDF5_HL  := $(or $(call archive_of,hdf5_hl),-lhdf5_hl)
  PKG_LIBS := $(foreach l,$(PKG_LIBS),$(if $(filter $(STATIC_CANDIDATES),$(l)),$(or $(call archive_of,$(l:-l%=%)),$(l)),$(l)))
  ifneq ($(call archive_of,hdf5),)
    PKG_LIBS += -lsz -lz -ldl   # what libhdf5.a needs (szip and deflate filters, plugins)
  endif
else
  HDF5_HL  := -lhdf5_hl
endif

WARN     := -Wall -Wextra -Wshadow -Wno-unused-parameter -Wno-format-truncation
ifeq ($(VARIANT),fuzz)
  WARN += -Wno-unknown-warning-option   # clang lacks -Wformat-truncation
endif
ifeq ($(WERROR),1)
  WARN += -Werror
endif

# -fno-math-errno: nothing reads errno after sqrt/exp, and a loop calling
# sqrt cannot vectorise while sqrt may set it (the MD pair kernels)
CFLAGS   := -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE $(OPT_$(VARIANT)) -fno-math-errno $(WARN) -I. -Itests \
            -fopenmp -Isolver -I$(OBJDIR)/gen $(PKG_CFLAGS) -MMD -MP
SAN_LD_asan := -fsanitize=address,undefined,float-cast-overflow
SAN_LD_fuzz := -fsanitize=address,undefined
LDFLAGS  := -fopenmp $(SAN_LD_$(VARIANT))
# hdf5_hl (H5LT: the small datasets and string attributes of h5out.c) has
# no pkg-config file of its own: it sits beside libhdf5 (whose -L is in
# PKG_LIBS) and comes before it (in the archive case it is in PKG_LIBS)
LDLIBS   := $(HDF5_HL) $(PKG_LIBS) -lm

# --- sources ---------------------------------------------------------------
UTIL_SRC     := $(wildcard solver/util/*.c)
SOLVER_SRC   := $(filter-out solver/main.c $(UTIL_SRC),$(shell find solver -name '*.c' | sort))
CAMPAIGN_SRC := $(filter-out campaign/main.c,$(wildcard campaign/*.c))
TEST_SRC     := $(wildcard tests/test_*.c)
TEST_HELPERS := $(wildcard tests/helpers/*.c)
# fuzz harnesses: linked into the test binary too (it replays their corpora)
FUZZ_SRC     := $(wildcard fuzz/*.c)

obj = $(patsubst %.c,$(OBJDIR)/%.o,$(1))

UTIL_LIB     := $(OBJDIR)/libcascade_util.a
SOLVER_LIB   := $(OBJDIR)/libcascade_solver.a
CAMPAIGN_LIB := $(OBJDIR)/libcascade_campaign.a

SOLVER_BIN   := $(BINDIR)/cascade-solver
CAMPAIGN_BIN := $(BINDIR)/cascade
TEST_BIN     := $(BINDIR)/cascade-tests
STANDIN_BIN  := $(BINDIR)/fake-solver

GEN_PROV     := $(OBJDIR)/gen/build_info.h

.PHONY: all deps test test-browser demo bench nightly reproduce soak install clean check-werror fuzz fuzz-deps fuzz-build fuzz-cmin
all: $(SOLVER_BIN) $(CAMPAIGN_BIN)

# --- dependencies (Debian) -------------------------------------------------
DEB_PKGS := build-essential pkg-config libsqlite3-dev libhdf5-openmpi-dev libgsl-dev \
            libopenmpi-dev openmpi-bin libyaml-dev libjansson-dev libcriterion-dev \
            gnuplot-nox lammps-data sqlite3 time bc hdf5-tools python3-ase lammps \
            slurm-wlm munge nettle-dev
deps:
	@missing=""; for p in $(DEB_PKGS); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q 'install ok installed' || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  cmd="apt-get install -y --no-install-recommends$$missing"; \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "deps: installing$$missing"; \
	    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$cmd) || { echo "deps: '$$cmd' failed" >&2; exit 1; }; \
	  else \
	    echo "deps: missing Debian packages:$$missing" >&2; \
	    echo "deps: run as root:  apt-get update && $$cmd" >&2; exit 1; \
	  fi; \
	fi

# --- provenance (rewritten only when it changes) ---------------------------
GIT_HASH := $(shell git rev-parse --short=12 HEAD 2>/dev/null || echo unknown)$(shell git diff --quiet HEAD -- 2>/dev/null || echo -dirty)
CC_VERSION := $(shell $(CC) --version 2>/dev/null | head -n1)
$(GEN_PROV): FORCE
	@mkdir -p $(dir $@)
	@printf '/* generated by the Makefile: build provenance */\n#define CASCADE_VERSION "%s"\n#define CASCADE_GIT_HASH "%s"\n#define CASCADE_COMPILER "%s"\n#define CASCADE_CFLAGS "%s"\n#define CASCADE_BUILD_VARIANT "%s"\n' \
	  '$(VERSION)' '$(GIT_HASH)' '$(CC_VERSION)' '$(OPT_$(VARIANT)) -fopenmp' '$(VARIANT)' > $@.tmp
	@cmp -s $@.tmp $@ 2>/dev/null && rm -f $@.tmp || mv $@.tmp $@
FORCE:

# --- compile ---------------------------------------------------------------
ifeq ($(V),1)
  Q :=
else
  Q := @
endif

$(OBJDIR)/%.o: %.c | $(GEN_PROV)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(CFLAGS) -c $< -o $@

$(UTIL_LIB): $(call obj,$(UTIL_SRC))
	@rm -f $@; ar rcs $@ $^
$(SOLVER_LIB): $(call obj,$(SOLVER_SRC))
	@rm -f $@; ar rcs $@ $^
$(CAMPAIGN_LIB): $(call obj,$(CAMPAIGN_SRC))
	@rm -f $@; ar rcs $@ $^

$(SOLVER_BIN): $(call obj,solver/main.c) $(SOLVER_LIB) $(UTIL_LIB)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(CAMPAIGN_BIN): $(call obj,campaign/main.c) $(CAMPAIGN_LIB) $(UTIL_LIB)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

$(TEST_BIN): $(call obj,$(TEST_SRC) $(TEST_HELPERS) $(FUZZ_SRC)) $(SOLVER_LIB) $(CAMPAIGN_LIB) $(UTIL_LIB)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS) -lcriterion

# The database schema and migrations are compiled into the campaign library.
DB_SQL  := db/schema.sql $(sort $(wildcard db/migrations/*.sql))
GEN_SQL := $(OBJDIR)/gen/db_sql.h
$(GEN_SQL): $(DB_SQL) campaign/embed_sql.sh
	@mkdir -p $(dir $@)
	@sh campaign/embed_sql.sh $(DB_SQL) > $@.tmp && mv $@.tmp $@
$(call obj,campaign/db_schema.c): $(GEN_SQL)

$(STANDIN_BIN): $(call obj,tests/standin/fake_solver.c) $(UTIL_LIB)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(LDLIBS)

# --- test, demo, bench -----------------------------------------------------
# Tests find the programs through these variables, so a sanitizer build tests
# sanitized programs.
TEST_ENV := CASCADE_SOLVER=$(abspath $(SOLVER_BIN)) CASCADE_BIN=$(abspath $(CAMPAIGN_BIN)) \
            CASCADE_STANDIN=$(abspath $(STANDIN_BIN)) CASCADE_ROOT=$(abspath .) \
            OMP_NUM_THREADS=2 ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$(abspath tests/lsan.supp) \
            UBSAN_OPTIONS=print_stacktrace=1 OMP_WAIT_POLICY=passive
# (passive: test processes run side by side with OpenMP threads; spinning
#  threads of one starve the others on a loaded machine)
CRITERION_JOBS ?= $(JOBS)

test: deps
	@$(MAKE) --no-print-directory $(SOLVER_BIN) $(CAMPAIGN_BIN) $(TEST_BIN) \
	    $(if $(wildcard tests/standin/fake_solver.c),$(STANDIN_BIN))
	$(TEST_ENV) $(TEST_BIN) --jobs $(CRITERION_JOBS) $(TEST_ARGS)

demo: deps
	@$(MAKE) --no-print-directory $(SOLVER_BIN) $(CAMPAIGN_BIN)
	CASCADE_SOLVER=$(abspath $(SOLVER_BIN)) sh bench/demo.sh $(abspath $(BINDIR))

# The nightly regressions (docs/nightly.md): each study of NIGHTLY_STUDIES runs
# (only the jobs this solver build has not run), every value and observed
# order is compared with the study's baseline (studies/baselines/), the
# report goes to reports/<study>/, and the target fails when any study
# regressed (all of them run either way); reports/nightly.html is the
# dashboard of all the nights so far.  NIGHTLY_ARGS=--update-baseline
# rewrites the baselines instead (review and commit them).
NIGHTLY_DIR ?= runs/nightly
NIGHTLY_STUDIES ?= studies/nightly.yaml studies/nightly_impact_quick.yaml \
                   studies/nightly_hugoniot_quick.yaml studies/md_timestep_refine_quick.yaml \
                   studies/nightly_damage_quick.yaml
nightly: deps
	@$(MAKE) --no-print-directory $(SOLVER_BIN) $(CAMPAIGN_BIN)
	@mkdir -p $(NIGHTLY_DIR)
	@fail=0; for s in $(NIGHTLY_STUDIES); do \
	    n=$$(basename $$s .yaml); \
	    echo "== $$s"; \
	    CASCADE_SOLVER=$(abspath $(SOLVER_BIN)) $(CAMPAIGN_BIN) regress $$s \
	        --db $(NIGHTLY_DIR)/cascade.db --runs $(NIGHTLY_DIR)/runs --out reports/$$n \
	        $(NIGHTLY_ARGS) || fail=1; \
	done; \
	$(CAMPAIGN_BIN) report --nightly --db $(NIGHTLY_DIR)/cascade.db --out reports/nightly.html \
	    || fail=1; \
	exit $$fail

# The two papers through the campaign (docs/reproduction.md): every study
# of studies/reproduction.tsv runs with `cascade run` (resuming), gets its
# `cascade report`, and reports/reproduce-$(REPRODUCE)/summary.md puts the
# papers' numbers beside ours.  REPRODUCE=quick (the default: small bars,
# one grid each, about half an hour on one idle core) or full (the papers'
# sizes and sweeps: many hours).  Not part of make test, which only checks
# the spec (studies/reproduce.sh check).
REPRODUCE ?= quick
reproduce: deps
	@$(MAKE) --no-print-directory $(SOLVER_BIN) $(CAMPAIGN_BIN)
	sh studies/reproduce.sh $(REPRODUCE) $(abspath $(BINDIR))

# The runner soak test (docs/campaign.md, "Soak test"): a few hundred
# stand-in jobs, several runners on one study, kill -9s of runners and
# solvers, frozen runners; then every job done exactly once, no lease left,
# the database consistent and every artifact's checksum right.  Not part of
# make test (a few minutes).  SOAK_JOBS, SOAK_KILLS, SOAK_RUNNERS,
# SOAK_SECONDS, SOAK_FREEZES, SOAK_LEASE, SOAK_SEED come from the environment
# or the make command line.
export SOAK_JOBS SOAK_KILLS SOAK_RUNNERS SOAK_SECONDS SOAK_FREEZES SOAK_LEASE SOAK_SEED
soak: deps
	@$(MAKE) --no-print-directory $(CAMPAIGN_BIN) $(STANDIN_BIN)
	bash bench/soak.sh $(abspath $(BINDIR))

# The nightly dashboard in a real browser (tests/browser/nightly_page.sh):
# installs Debian's chromium for itself (not part of make deps or make
# test), renders `cascade report --nightly` headless, checks every figure
# drew, and keeps the screenshot in build/test-browser/nightly.png.
BROWSER_DEB_PKGS := chromium python3
test-browser:
	@$(MAKE) --no-print-directory deps DEB_PKGS="$(DEB_PKGS) $(BROWSER_DEB_PKGS)"
	@$(MAKE) --no-print-directory $(CAMPAIGN_BIN) $(STANDIN_BIN)
	sh tests/browser/nightly_page.sh $(abspath $(BINDIR)) build/test-browser

bench: deps
	@$(MAKE) --no-print-directory BUILD=release all
	sh bench/bench.sh $(abspath build/release/bin)

# --- fuzzing (docs/fuzzing.md) ----------------------------------------------
# One libFuzzer target per input reader, FUZZ_PARALLEL at a time (default
# one after the other) for FUZZ_SECONDS each over tests/fuzz/corpus/<reader>/; inputs
# that add coverage are merged back into the corpus, crashing inputs land in
# tests/fuzz/crashes/<reader>/ (make test replays both).  Logs and the
# inputs of the session in build/fuzz/.
FUZZ_SECONDS ?= 60
FUZZ_MAX_LEN ?= 8192
FUZZ_NAMES   := case study lammps_data extxyz eam sw meam_spline result_json baseline
FUZZ_TARGETS ?= $(FUZZ_NAMES)
FUZZ_ARGS    ?=
FUZZ_PARALLEL ?= 1
export FUZZ_ARGS
FUZZ_BINDIR  := build/fuzz/bin
FUZZ_DEB_PKGS := clang libclang-rt-14-dev libomp-14-dev

fuzz-deps:
	@$(MAKE) --no-print-directory deps DEB_PKGS="$(DEB_PKGS) $(FUZZ_DEB_PKGS)"

fuzz-build: $(FUZZ_NAMES:%=$(FUZZ_BINDIR)/fuzz_%)

$(FUZZ_BINDIR)/fuzz_%: $(OBJDIR)/fuzz/fuzz_%.o $(OBJDIR)/fuzz/common.o $(SOLVER_LIB) \
                       $(CAMPAIGN_LIB) $(UTIL_LIB)
	@mkdir -p $(dir $@)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -fsanitize=fuzzer -o $@ $^ $(LDLIBS)

fuzz: fuzz-deps
	@$(MAKE) --no-print-directory BUILD=fuzz fuzz-build
	@bash fuzz/run.sh $(FUZZ_BINDIR) $(FUZZ_SECONDS) $(FUZZ_MAX_LEN) $(FUZZ_PARALLEL) $(FUZZ_TARGETS)

# Shrink each corpus to the inputs that keep its coverage (the seed-* files
# of fuzz/seed.sh always stay).
fuzz-cmin: fuzz-deps
	@$(MAKE) --no-print-directory BUILD=fuzz fuzz-build
	@for t in $(FUZZ_TARGETS); do \
	    corpus=tests/fuzz/corpus/$$t; min=build/fuzz/cmin/$$t; \
	    rm -rf $$min; mkdir -p $$min; cp $$corpus/seed-* $$min/ 2>/dev/null; \
	    LSAN_OPTIONS=suppressions=$(abspath tests/lsan.supp) OMP_NUM_THREADS=1 \
	    $(FUZZ_BINDIR)/fuzz_$$t -merge=1 -max_len=$(FUZZ_MAX_LEN) -timeout=10 $$min $$corpus \
	        > build/fuzz/cmin/$$t.log 2>&1 || { echo "fuzz-cmin $$t failed" >&2; exit 1; }; \
	    echo "fuzz-cmin $$t: $$(ls $$corpus | wc -l) -> $$(ls $$min | wc -l) files"; \
	    rm -rf $$corpus; mv $$min $$corpus; \
	done

install: all
	install -d $(DESTDIR)$(PREFIX)/bin $(DESTDIR)$(PREFIX)/share/cascade
	install -m 755 $(SOLVER_BIN) $(CAMPAIGN_BIN) $(DESTDIR)$(PREFIX)/bin/
	cp -r db docs $(DESTDIR)$(PREFIX)/share/cascade/

clean:
	rm -rf build bin

-include $(shell find build/$(VARIANT)/obj -name '*.d' 2>/dev/null)
