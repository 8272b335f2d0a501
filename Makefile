# clothbench — see README.md. `make help` prints the lines starting with ##.
##
## make test          install missing Debian packages, build, run the fast tests (about a minute once built):
##                     unit tests, CLI, layers, and a --smoke run of every experiment, checked
## make check-all     the long tests (CI): every experiment's --quick run (CSV convention,
##                     determinism, shards), GNU parallel and a real local Slurm running shards
##                     (tests/parallel.sh, tests/slurm.sh), then make san and make fuzz
## make experiments   install missing packages, run every experiment, then plots and report
## make all           build the library, simulate, the experiments, bench and report
## make plots         draw plots/out/*.png and .svg from results/*.csv (gnuplot)
## make movies        animated GIFs of paired runs (explicit blow-up, Baraff-Witkin vs Newton, drape, locking fold)
## make report        decide every claim from results/*.csv into results/REPORT.md
## make compare       results/ against the committed reference run of the nearest CPU (results/reference/<cpu>/):
##                     claim by claim, both verdicts and the deciding timings with their spreads; fails when a
##                     verdict differs outside the spreads
## make reference     keep the last full run as this CPU's reference (results/reference/<cpu>/, committed)
## make bench         the benchmarks (results/bench_core.csv, bench_nonlinear.csv, bench_broadphase.csv, bench_contact.csv);
##                     SCALE=1 adds the scaling run to 1024^2 (results/bench_scale.csv, ~15 min);
##                     make experiments SCALE=1 adds J4's 1024^2 size to linear_solvers (about 1.5 h more)
## make check         make test without the package step;  make check-quick  check-all's --quick part
## make determinism   every experiment's --quick run twice, compared (timing columns aside)
## make san           make check under AddressSanitizer + UndefinedBehaviorSanitizer (build/san)
## make fuzz          libFuzzer on the config parser, OBJ reader, scene building (FUZZ_SECONDS=60)
## make coverage      gcov line coverage of lib/ and lib/core/ from the unit tests and smoke runs (build/cov)
## make deps          install the missing Debian packages (or print the command)
## make format-check  clang-format 14 --dry-run -Werror over the C sources and headers (.clang-format)
## make format        the same, rewriting the files in place
## make clean         remove build/;  make distclean  also results/ and plots/out/
##
## knobs: WERROR=1 (warnings are errors), QUICK=1 (reduced sweeps), JOBS=n (experiments at a time; default the cores),
##        THREADS=n (threads of OpenBLAS and of CHOLMOD's OpenMP regions, for
##        experiments and bench; default 1), RUN_SHARDS="name:N ..." (experiments that
##        make experiments runs as N processes, merged; default locking:JOBS)

CC      ?= gcc
OPT     ?= -O2
WERROR  ?= 0
QUICK   ?= 0
THREADS ?= 1
BUILD   ?= build
SAN     ?=

MULTIARCH   := $(shell $(CC) -print-multiarch 2>/dev/null)
OPENBLAS_INC := $(firstword $(wildcard $(addprefix /usr/include/$(MULTIARCH)/,openblas-pthread openblas-openmp openblas-serial)))

WARN := -std=c11 -Wall -Wextra -Wpedantic -Wshadow -Wmissing-prototypes
ifeq ($(WERROR),1)
WARN += -Werror
endif
# Layers, each compiled with only its own include paths, so the direction is
# enforced by the build: a core file that includes an instrument or I/O header
# does not compile (tests/layers.sh checks that it does not).
# Order: core <- config <- instruments <- io <- programs.
#   base         lib/base/: header-only building blocks (vec.h, rng.h) every layer may use
#   core         include/clothbench/ (public API) + lib/core/<room>/ (internal headers);
#                the rooms: model, energy, geometry, integrator, solver, util
#   config       lib/config/: the INI key table and its binding to core structs
#   instruments  lib/instruments/: measurements on core objects (the thread probe too)
#   io           lib/io/: what every program shares (CSV writing, provenance, progress);
#                it writes the instruments' measurements (timings, observed threads)
#   programs     tools/, experiments/<name>/, bench/, claims/, tests/: everything
SYS_INC     := -I/usr/include/suitesparse $(if $(OPENBLAS_INC),-I$(OPENBLAS_INC))
# lib/core in rooms by kind (CONTRIBUTING.md, "Layout"): each room's internal headers are
# visible to the whole core and to nothing above it
CORE_ROOMS  := $(patsubst %/,%,$(sort $(dir $(wildcard lib/core/*/*.[ch]))))
CORE_INC    := -Iinclude -Ilib/base $(addprefix -I,$(CORE_ROOMS))
CONFIG_INC  := -Iinclude -Ilib/base -Ilib/config
INSTR_INC   := -Iinclude -Ilib/base -Ilib/config -Ilib/instruments
IO_INC      := -Iinclude -Ilib/base -Ilib/config -Ilib/instruments -Ilib/io
PROGRAM_INC := -Iinclude -Ilib/base -Ilib/config -Ilib/instruments -Ilib/io -Iclaims
CPPFLAGS := -D_POSIX_C_SOURCE=200809L $(SYS_INC)
CFLAGS   := $(OPT) -g $(WARN) $(SAN)
LDFLAGS  := $(SAN)
# GSL is linked statically: Debian's libgsl.so pulls in libgslcblas, and we
# link exactly one CBLAS, OpenBLAS (scripts/check-blas.sh verifies it).
LDLIBS   := -lcholmod -Wl,-Bstatic -lgsl -Wl,-Bdynamic -lopenblas -linih -lgmp -lgomp -lm

CORE_SRC  := $(sort $(wildcard lib/core/*/*.c))
CONFIG_SRC:= $(sort $(wildcard lib/config/*.c))
INSTR_SRC := $(sort $(wildcard lib/instruments/*.c))
IO_SRC    := $(sort $(wildcard lib/io/*.c))
LIB_OBJ  := $(CORE_SRC:%.c=$(BUILD)/%.o) $(CONFIG_SRC:%.c=$(BUILD)/%.o) $(INSTR_SRC:%.c=$(BUILD)/%.o) $(IO_SRC:%.c=$(BUILD)/%.o) $(BUILD)/version.o
LIB      := $(BUILD)/libclothbench.a
TOOLS    := $(BUILD)/simulate $(BUILD)/blas-kernel $(BUILD)/ccd-query $(BUILD)/slope-sweep
CCD_GEN  := $(BUILD)/ccd-gen
# one program per folder experiments/<name>/ (main.c plus what serves only it)
EXP_NAMES:= $(sort $(notdir $(patsubst %/,%,$(dir $(wildcard experiments/*/main.c)))))
EXPS     := $(EXP_NAMES:%=$(BUILD)/%)
exp_obj   = $(patsubst %.c,$(BUILD)/%.o,$(sort $(wildcard experiments/$(1)/*.c)))
BENCH_SRC:= $(sort $(wildcard bench/*.c))
BENCHES  := $(BENCH_SRC:bench/%.c=$(BUILD)/%)
# bench_peers needs MUMPS and SuperLU: make all builds it where they are installed, make bench installs them
PEER_PKGS := libmumps-seq-dev libsuperlu-dev
PEER_HDRS := /usr/include/dmumps_c.h /usr/include/superlu/slu_ddefs.h
ALL_BENCHES := $(if $(filter-out $(wildcard $(PEER_HDRS)),$(PEER_HDRS)),$(filter-out $(BUILD)/bench_peers,$(BENCHES)),$(BENCHES))
REPORT_SRC := $(filter-out claims/main.c,$(sort $(wildcard claims/*.c)))
REPORT_LIB := $(BUILD)/libreport.a
TEST_SRC := $(sort $(wildcard tests/test_*.c))
TESTS    := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
TEST_OBJ := $(BUILD)/tests/support.o

help:
	@sed -n 's/^##  \{0,1\}//p' $(firstword $(MAKEFILE_LIST))

.PHONY: help determinism all ccd-set test check check-all check-quick check-cluster experiments run-experiments plots movies report compare reference bench san fuzz fuzz-build coverage coverage-build deps format format-check clean distclean FORCE
.DEFAULT_GOAL := all

all: $(LIB) $(TOOLS) $(CCD_GEN) $(EXPS) $(ALL_BENCHES) $(BUILD)/report

deps:
	@scripts/deps.sh

# ---- build -------------------------------------------------------------------

$(BUILD)/version.c: FORCE
	@scripts/version.sh $@ $(CFLAGS)

# the nonlinear iterations' kernels: sqrt without errno (so that the compiler
# may vectorise it; sqrtpd rounds as sqrt does) and the vectoriser's full cost
# model; no FMA contraction (-std=c11), so results stay bit for bit.
# VECINFO=1 prints what vectorised (-fopt-info-vec).
# gcc-only flags stay out of clang builds (make fuzz compiles lib/ with clang)
KERNEL_CFLAGS = -fno-math-errno $(if $(findstring clang,$(CC)),,-fvect-cost-model=dynamic $(if $(filter 1,$(VECINFO)),-fopt-info-vec-optimized))
$(BUILD)/lib/core/energy/energy_spring.o $(BUILD)/lib/core/energy/nl_kernel.o $(BUILD)/lib/core/integrator/integrator_nljacobi.o $(BUILD)/lib/core/integrator/integrator_pd.o: CFLAGS += $(KERNEL_CFLAGS)
# the PETSc solver family (lib/core/solver/solver_petsc.c) compiles against PETSc's and MPI's headers when they are
# installed and loads libpetsc at run time (dlopen): programs that solve without PETSc never load it
PETSC_CFLAGS := $(shell pkg-config --cflags PETSc mpi 2>/dev/null | sed 's/-I/-isystem /g')
$(BUILD)/lib/core/solver/solver_petsc.o: CPPFLAGS += $(if $(PETSC_CFLAGS),-DCB_HAVE_PETSC $(PETSC_CFLAGS))
$(BUILD)/lib/core/%.o: lib/core/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CORE_INC) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/lib/config/%.o: lib/config/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CONFIG_INC) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/lib/instruments/%.o: lib/instruments/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(INSTR_INC) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/lib/io/%.o: lib/io/%.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(IO_INC) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(PROGRAM_INC) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/version.o: $(BUILD)/version.c
	$(CC) $(CPPFLAGS) $(IO_INC) $(CFLAGS) -c $< -o $@

$(LIB): $(LIB_OBJ)
	@rm -f $@
	ar rcs $@ $^

$(REPORT_LIB): $(REPORT_SRC:%.c=$(BUILD)/%.o)
	@rm -f $@
	ar rcs $@ $^

$(BUILD)/report: $(BUILD)/claims/main.o $(REPORT_LIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/simulate: $(BUILD)/tools/simulate.o $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/blas-kernel: $(BUILD)/tools/blas_kernel.o $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/ccd-query: $(BUILD)/tools/ccd_query.o $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/slope-sweep: $(BUILD)/tools/slope_sweep.o $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

# the generator of the exact CCD query set tests/ccd/ (docs/geometry-ccd.md): GMP only, no library;
# `make ccd-set` rewrites the committed files
$(CCD_GEN): $(BUILD)/tests/ccd/gen.o
	$(CC) $(LDFLAGS) $^ -lgmp -lm -o $@
ccd-set: $(CCD_GEN)
	$(CCD_GEN) tests/ccd

.SECONDEXPANSION:
$(EXPS): $(BUILD)/%: $$(call exp_obj,%) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

# every bench program links bench/support/ (the allocation counter, the triad)
BENCH_SUPPORT := $(patsubst %.c,$(BUILD)/%.o,$(wildcard bench/support/*.c))
# the counter and the BLAS profile take libc's and the Fortran BLAS's names at
# the link, so every call of the process (CHOLMOD's too) reaches them
BENCH_INTERPOSE := $(foreach f,malloc calloc realloc memalign posix_memalign aligned_alloc,-Wl,--defsym=$(f)=cb_bench_$(f)) \
                   $(foreach f,dgemm dsyrk dtrsm dpotrf,-Wl,--defsym=$(f)_=cb_bench_$(f))
$(BUILD)/%: $(BUILD)/bench/%.o $(BENCH_SUPPORT) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) $(BENCH_INTERPOSE) -o $@
# the peers bench_peers compares with (MUMPS, SuperLU): linked into it only, never the library
$(BUILD)/bench/bench_peers.o: CPPFLAGS += -I/usr/include/superlu
$(BUILD)/bench_peers: LDLIBS += -ldmumps_seq -lsuperlu
# Embree (rtcCollide), the broad phase's comparison: linked into bench_broadphase only
$(BUILD)/bench_broadphase: LDLIBS += -lembree3

$(BUILD)/tests/%: $(BUILD)/tests/%.o $(TEST_OBJ) $(REPORT_LIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -lcriterion -o $@
# the broad phase's test compares the candidate sets with the code before the float boxes (bench/support/bp_old.c)
$(BUILD)/tests/test_broadphase.o: CPPFLAGS += -Ibench/support
$(BUILD)/tests/test_broadphase: $(BUILD)/tests/test_broadphase.o $(BUILD)/bench/support/bp_old.o $(TEST_OBJ) $(REPORT_LIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -lcriterion -o $@
# the allocation-failure test routes CHOLMOD's allocations (SuiteSparse_config) through the counter
$(BUILD)/tests/test_enomem: LDLIBS += -lsuitesparseconfig

# ---- tests -------------------------------------------------------------------

# Three tiers (docs/testing.md):
#   make test       deps, then check: the unit tests, the CLI, report, lock and
#                   layer checks, and a --smoke run of every experiment (one
#                   small cell of each sweep) that the CSV-convention test, the
#                   report and the shard tests read: about a minute
#   make check-all  check (unless it passed on this build), then check-quick,
#                   check-cluster,
#                   san and fuzz: what CI runs before the quick experiments
#   check-quick     every experiment's --quick run once, the CSV convention on
#                   it, a second run compared with it (determinism), the shards,
#                   the verdicts over the recorded spread (tests/spread.sh)
#   check-cluster   GNU parallel and a real local Slurm running shards (check-all)
# `make test` = deps, then the build and the checks in a second make, so that
# nothing compiles before the packages are there.
test: deps
	@$(MAKE) --no-print-directory check

SMOKE_DIR := $(BUILD)/smoke
QUICK_DIR := $(BUILD)/quick
# experiment shard-count: the shard tests (main and side tables merged back)
SHARDS := topology:3 definiteness:2 nonlinear:2 newton_vs_bw:2 contact:2
shard_tests = @set -e; for s in $(SHARDS); do BUILD=$(BUILD) UNSHARDED_DIR=$(2) tests/shard.sh $(1) $${s%%:*} $${s\#\#*:}; done

check: $(TESTS) $(TOOLS) $(EXPS) $(BUILD)/report
	@rm -f $(BUILD)/check.passed
	@scripts/check-blas.sh $(BUILD)/simulate
	@set -e; for t in $(TESTS); do echo "== $$t"; CB_QUIET=1 CB_SIMULATE=$(BUILD)/simulate $$t --jobs 2 --short-filename; done
	@BUILD=$(BUILD) tests/cli.sh
	@BUILD=$(BUILD) tests/lock.sh
	@BUILD=$(BUILD) tests/scripts.sh
	@BUILD=$(BUILD) tests/hardening.sh
	@CC="$(CC)" CPPFLAGS="$(CPPFLAGS)" CORE_INC="$(CORE_INC)" CONFIG_INC="$(CONFIG_INC)" INSTR_INC="$(INSTR_INC)" IO_INC="$(IO_INC)" tests/layers.sh
	@BUILD=$(BUILD) tests/experiments.sh --smoke $(SMOKE_DIR) $(EXP_NAMES)
	@BUILD=$(BUILD) tests/csv_convention.sh --runs $(SMOKE_DIR)
	@BUILD=$(BUILD) SMOKE_DIR=$(SMOKE_DIR) tests/report.sh
	@BUILD=$(BUILD) SMOKE_DIR=$(SMOKE_DIR) tests/compare.sh
	@BUILD=$(BUILD) tests/spread.sh
	$(call shard_tests,--smoke,$(SMOKE_DIR))
	@touch $(BUILD)/check.passed
	@echo "all tests passed"

# make check-all skips check if it passed since anything it tests changed
# (so CI's make test, then make check-all, runs it once); a check that fails
# or is interrupted leaves no stamp
$(BUILD)/check.passed: $(TESTS) $(TOOLS) $(EXPS) $(BUILD)/report Makefile README.md docs/config.md docs/csv_columns.txt \
  $(wildcard tests/*.sh scripts/*.sh scripts/lib/*.sh configs/*.ini plots/*.gp)
	@$(MAKE) --no-print-directory check

check-all: deps
	@scripts/deps.sh $(CLUSTER_PKGS)
	@$(MAKE) --no-print-directory $(BUILD)/check.passed
	@$(MAKE) --no-print-directory check-quick
	@$(MAKE) --no-print-directory check-cluster
	@$(MAKE) --no-print-directory san
	@$(MAKE) --no-print-directory fuzz
	@echo "check-all: all tests passed"

# The quick runs go CHECK_JOBS at a time (default: the cores), longest first
# (QUICK_FIRST; the rest follow), each with a CPU lock of its own: their
# timings are blanked by every check here, never published. The second run of
# each (tests/rerun.sh) is its determinism check, as N merged shards for the
# experiments in SHARDS (the shard test) and whole for the others.
CHECK_JOBS ?= $(shell getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
QUICK_FIRST := nonlinear explicit_stability locking linear_solvers newton_vs_bw field
QUICK_ORDER = $(filter $(EXP_NAMES),$(QUICK_FIRST)) $(filter-out $(QUICK_FIRST),$(EXP_NAMES))
check-quick: $(EXPS) $(TOOLS) $(BUILD)/report
	@BUILD=$(BUILD) tests/experiments.sh -j $(CHECK_JOBS) --quick $(QUICK_DIR) $(QUICK_ORDER)
	@BUILD=$(BUILD) tests/csv_convention.sh --runs $(QUICK_DIR)
	@BUILD=$(BUILD) tests/rerun.sh -j $(CHECK_JOBS) --quick $(QUICK_DIR) "$(SHARDS)" $(QUICK_ORDER)
	@BUILD=$(BUILD) tests/spread.sh $(QUICK_DIR)

# the cluster runners (docs/running.md, "Running on a cluster"): scripts/parallel-run.sh
# under GNU parallel, with an interrupted run that resumes, and
# scripts/slurm-submit.sh against a real Slurm started on this machine
# (munged, slurmctld, slurmd; needs root), each merged run compared with the
# one-process run's CSVs
CLUSTER_PKGS := slurm-wlm munge parallel
check-cluster: $(EXPS) $(BUILD)/report
	@BUILD=$(BUILD) tests/parallel.sh
	@BUILD=$(BUILD) tests/slurm.sh

# every experiment's --quick run twice: identical CSVs apart from the date and
# the timing columns (check-quick does it with one run fewer, against its own)
determinism: $(EXPS)
	@set -e; for x in $(EXP_NAMES); do BUILD=$(BUILD) tests/determinism.sh $$x; done

# the sanitizers on check: the unit tests and the smoke set
# tests/lsan.supp: what PETSc's MPI keeps for the process (not our memory)
san: deps
	@LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 $(MAKE) --no-print-directory BUILD=build/san OPT=-O1 \
	  SAN="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" check

# ---- coverage: gcov line coverage of lib/ (not part of make test)
# lib/, the tests and the programs compiled with --coverage at -O0 in
# build/cov/; scripts/coverage.sh runs the unit tests, the CLI tests and the
# --smoke runs there, reports lib/ and lib/core/ (gcovr) and rewrites the
# coverage block of docs/testing.md; it fails when lib/core/ is under COVERAGE_MIN %.
COVERAGE_MIN ?= 85

coverage:
	@scripts/deps.sh gcovr
	@$(MAKE) --no-print-directory BUILD=build/cov OPT=-O0 SAN="--coverage" coverage-build
	@BUILD=build/cov COVERAGE_MIN=$(COVERAGE_MIN) scripts/coverage.sh $(EXP_NAMES)

coverage-build: $(TESTS) $(TOOLS) $(EXPS)

# ---- fuzzing: clang's libFuzzer on the config parser, the OBJ reader, scene building and the report (fuzz_report: the checkers on crafted CSVs)
# The library is compiled with coverage (fuzzer-no-link) and ASan + UBSan in
# build/fuzz/; each harness fuzz/fuzz_<name>.c runs FUZZ_SECONDS (default 60).

FUZZ_SECONDS ?= 60
FUZZ_SRC := $(sort $(wildcard fuzz/fuzz_*.c))
FUZZ_PKGS := clang libclang-rt-14-dev

fuzz:
	@scripts/deps.sh $(FUZZ_PKGS)
	@$(MAKE) --no-print-directory BUILD=build/fuzz CC=clang OPT="-O1" \
	  SAN="-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" fuzz-build
	@BUILD=build/fuzz FUZZ_SECONDS=$(FUZZ_SECONDS) scripts/fuzz.sh

fuzz-build: $(FUZZ_SRC:fuzz/%.c=$(BUILD)/%)

# the report's harness links the checkers (claims/) too
$(BUILD)/fuzz_report: $(BUILD)/fuzz/fuzz_report.o $(REPORT_LIB) $(LIB)
	$(CC) $(LDFLAGS) -fsanitize=fuzzer $^ $(LDLIBS) -o $@
$(BUILD)/fuzz_%: $(BUILD)/fuzz/fuzz_%.o $(LIB)
	$(CC) $(LDFLAGS) -fsanitize=fuzzer $^ $(LDLIBS) -o $@

# ---- experiments, plots, report ------------------------------------------------

# The environment of every program make starts: the thread counts, and
# build/blas-kernel in front, which executes the program with the best safe
# OpenBLAS kernel (OPENBLAS_CORETYPE, when OpenBLAS falls back to kernels
# below what the CPU supports and the kernel passes its self-test, cached in
# $(BUILD)/blas-kernel.cache; tools/blas_kernel.c). A set OPENBLAS_CORETYPE
# is left as it is.
BLAS_KERNEL := $(BUILD)/blas-kernel
EXP_ENV := OPENBLAS_NUM_THREADS=$(THREADS) OMP_NUM_THREADS=$(THREADS) $(BLAS_KERNEL) --cache $(BUILD)/blas-kernel.cache
EXP_CSV := $(EXP_NAMES:%=results/%.csv)

# After a full run (not QUICK=1), the numbers in README.md and docs/ (docs/experiments/ too)
# are regenerated from the new results (build/report --fill): they are never typed.
DOC_FILL := README.md $(wildcard docs/*.md docs/experiments/*.md)

experiments: deps
	@$(MAKE) --no-print-directory run-experiments
	@$(MAKE) --no-print-directory plots movies report
	@tests/csv_convention.sh --results results
ifneq ($(QUICK),1)
	@$(EXP_ENV) $(BUILD)/report --results results --fill-only $(addprefix --fill ,$(DOC_FILL))
	@$(PYTHON) scripts/timed-split.py --doc docs/running.md results
endif

# JOBS experiments at a time (default: the cores), longest first: the CPU lock
# keeps every timed experiment, and every timed cell of the experiments that
# lock per cell (cb_experiment_timed_cells), alone on the machine, while
# untimed work fills the other cores (docs/running.md, "Every core")
JOBS ?= $(CHECK_JOBS)
run-experiments: $(EXPS) $(BLAS_KERNEL)
	@$(MAKE) --no-print-directory -j$(JOBS) $(QUICK_ORDER:%=results/%.csv.run)

# Experiments run as several processes, EXPERIMENT:N each (default: locking as
# JOBS processes when JOBS > 1): their --shard I/N runs go to results/shards/
# as jobs of their own, and scripts/merge-shards.sh merges them into
# results/<name>.csv, the CSVs of the unsharded run (tests/shard.sh). Locking's
# untimed cells (F1's anisotropy sweep: 24 of its 25 minutes) run one after
# another in one process, and that alone set the whole run's lower bound on 2
# cores (docs/running.md, "The split and the bound"). RUN_SHARDS= runs every
# experiment whole.
RUN_SHARDS ?= $(if $(filter-out 0 1,$(JOBS)),locking:$(JOBS))
quick_flag = $(if $(filter 1,$(QUICK)),--quick)
define run_sharded
results/$(1).csv.run: $(foreach i,$(shell seq 1 $(2)),results/shards/$(1)-$(i)of$(2).run)
	@echo "scripts/merge-shards.sh results/$(1).csv $$(^:.run=.csv)"
	@scripts/merge-shards.sh results/$(1).csv $$(^:.run=.csv)
	@scripts/shard-runtime.sh $(if $(filter 1,$(QUICK)),1,0) $$^ > results/$(1).runtime.tmp && mv results/$(1).runtime.tmp results/$(1).runtime

results/shards/$(1)-%of$(2).run: $(BUILD)/$(1) $(BLAS_KERNEL) FORCE
	@mkdir -p results/shards
	@t0=$$$$(date +%s.%N); \
	echo "$(EXP_ENV) $(BUILD)/$(1) $(quick_flag) --shard $$*/$(2) --out results/shards/$(1)-$$*of$(2).csv"; \
	$(EXP_ENV) $(BUILD)/$(1) $(quick_flag) --shard $$*/$(2) --out results/shards/$(1)-$$*of$(2).csv || exit $$$$?; \
	t1=$$$$(date +%s.%N); \
	{ echo "start_s: $$$$t0"; echo "end_s: $$$$t1"; cat results/shards/$(1)-$$*of$(2).csv.split; } > $$@.tmp && mv $$@.tmp $$@
endef
$(foreach s,$(RUN_SHARDS),$(eval $(call run_sharded,$(word 1,$(subst :, ,$(s))),$(word 2,$(subst :, ,$(s))))))

# each run records its wall time in results/<name>.runtime (for the report's run-time table)
results/%.csv.run: $(BUILD)/% $(BLAS_KERNEL)
	@mkdir -p results
	@t0=$$(date +%s.%N); \
	echo "$(EXP_ENV) $(BUILD)/$* $(if $(filter 1,$(QUICK)),--quick) --out results/$*.csv"; \
	$(EXP_ENV) $(BUILD)/$* $(if $(filter 1,$(QUICK)),--quick) --out results/$*.csv || exit $$?; \
	t1=$$(date +%s.%N); \
	{ awk -v a=$$t0 -v b=$$t1 -v q=$(QUICK) 'BEGIN { printf "wall_s: %.1f\nquick: %d\n", b - a, q == 1 }'; \
	  cat results/$*.csv.split 2>/dev/null; } > results/$*.runtime; rm -f results/$*.csv.split

plots:
	@scripts/plots.sh

# animated GIFs of paired runs (scripts/movies.sh lists them); the report embeds them
movies: deps $(TOOLS)
	@BUILD=$(BUILD) $(EXP_ENV) scripts/movies.sh

# the report program is a prerequisite (built under this make's jobserver), so
# scripts/report.sh does not call make itself
report: $(BUILD)/report $(BLAS_KERNEL)
	@BUILD=$(BUILD) $(EXP_ENV) scripts/report.sh

compare: $(BUILD)/report
	@BUILD=$(BUILD) scripts/compare.sh results

# the last full run becomes this CPU's reference (results/reference/<cpu>/, committed)
reference:
	@scripts/store-reference.sh results

# Debian's python3 (its python3-scipy), whatever python3 the PATH finds first
PYTHON ?= /usr/bin/python3

bench: deps
	@scripts/deps.sh python3-scipy $(PEER_PKGS)
	@$(MAKE) --no-print-directory $(BENCHES) $(BLAS_KERNEL)
	@mkdir -p results
	@rm -f $(BUILD)/bench_matrix_*.bin
	CB_BENCH_MATRIX_DIR=$(BUILD) $(EXP_ENV) $(BUILD)/bench_core $(if $(filter 1,$(QUICK)),--quick) --out results/bench_core.csv
	$(EXP_ENV) $(PYTHON) bench/spmv_scipy.py $(BUILD)/bench_spmv $(BUILD) results/bench_scipy.csv
	CB_BENCH_MATRIX_DIR=$(BUILD) $(EXP_ENV) $(BUILD)/bench_peers $(if $(filter 1,$(QUICK)),--quick) --out results/bench_peers.csv
	$(EXP_ENV) $(PYTHON) bench/peers_scipy.py $(if $(filter 1,$(QUICK)),--quick) $(BUILD)/bench_peers $(BUILD) results/bench_peers_scipy.csv
	$(PYTHON) scripts/readme-peers.py results docs/performance.md
	$(PYTHON) scripts/readme-perf.py results docs/performance.md
	$(EXP_ENV) $(BUILD)/bench_nonlinear --out results/bench_nonlinear.csv
	$(PYTHON) scripts/readme-bench-nonlinear.py results docs/performance.md
	$(EXP_ENV) $(BUILD)/bench_pd_matrix $(if $(filter 1,$(QUICK)),--quick) --out results/bench_pd_matrix.csv
	$(EXP_ENV) $(BUILD)/bench_broadphase $(if $(filter 1,$(QUICK)),--quick) --out results/bench_broadphase.csv
	$(EXP_ENV) $(BUILD)/bench_contact $(if $(filter 1,$(QUICK)),--quick) --out results/bench_contact.csv
	$(PYTHON) scripts/readme-bench-contact.py results docs/performance.md
ifeq ($(SCALE),1)
	$(EXP_ENV) $(BUILD)/bench_scale --out results/bench_scale.csv
	$(PYTHON) scripts/readme-bench-scale.py results docs/performance.md
endif

# ---- source format: .clang-format, by Debian 12's clang-format 14 ------------------
CLANG_FORMAT ?= clang-format-14
FORMAT_SRC := $(sort $(wildcard include/clothbench/*.h lib/*/*.[ch] lib/core/*/*.[ch] tools/*.c experiments/*/*.[ch] claims/*.[ch] \
  tests/*.[ch] bench/*.c bench/support/*.[ch] fuzz/*.[ch]))

format-check:
	@scripts/deps.sh clang-format-14
	@$(CLANG_FORMAT) --dry-run -Werror $(FORMAT_SRC) && echo "format-check: $(words $(FORMAT_SRC)) files formatted"

format:
	@scripts/deps.sh clang-format-14
	$(CLANG_FORMAT) -i $(FORMAT_SRC)

clean:
	rm -rf build

distclean: clean
	rm -rf results plots/out

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
.SECONDARY:
