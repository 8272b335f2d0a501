# clothbench — see README.md. `make help` prints the lines starting with ##.
##
## make test          install missing Debian packages, build, run the tests
## make experiments   install missing packages, run every experiment, then plots and report
## make all           build the library, simulate, the experiments, bench and report
## make plots         draw plots/out/*.png and .svg from results/*.csv (gnuplot)
## make movies        animated GIFs of paired runs (explicit blow-up, Baraff-Witkin vs Newton, drape, locking fold)
## make report        decide every claim from results/*.csv into results/REPORT.md
## make bench         the benchmarks (results/bench_core.csv, results/bench_nonlinear.csv)
## make determinism  every experiment's --quick run twice, compared (timing columns aside)
## make san           the tests under AddressSanitizer + UndefinedBehaviorSanitizer
## make fuzz          libFuzzer on the config parser, OBJ reader, scene building (FUZZ_SECONDS=60)
## make deps          install the missing Debian packages (or print the command)
## make clean         remove build/;  make distclean  also results/ and plots/out/
##
## knobs: WERROR=1 (warnings are errors), QUICK=1 (reduced sweeps),
##        THREADS=n (threads of OpenBLAS and of CHOLMOD's OpenMP regions, for
##        experiments and bench; default 1)

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
# Order: core <- config <- {instruments, io} <- programs.
#   core         include/clothbench/ (public API) + lib/core/ (internal headers)
#   config       lib/config/: the INI key table and its binding to core structs
#   instruments  lib/instruments/: measurements on core objects
#   io           lib/io/: what every program shares (CSV, provenance, progress)
#   programs     tools/, experiments/<name>/, bench/, claims/, tests/: everything
SYS_INC     := -I/usr/include/suitesparse $(if $(OPENBLAS_INC),-I$(OPENBLAS_INC))
CORE_INC    := -Iinclude -Ilib/core
CONFIG_INC  := -Iinclude -Ilib/config
INSTR_INC   := -Iinclude -Ilib/config -Ilib/instruments
IO_INC      := -Iinclude -Ilib/config -Ilib/io
PROGRAM_INC := -Iinclude -Ilib/config -Ilib/instruments -Ilib/io -Iclaims
CPPFLAGS := -D_POSIX_C_SOURCE=200809L $(SYS_INC)
CFLAGS   := $(OPT) -g $(WARN) $(SAN)
LDFLAGS  := $(SAN)
# GSL is linked statically: Debian's libgsl.so pulls in libgslcblas, and we
# link exactly one CBLAS, OpenBLAS (scripts/check-blas.sh verifies it).
LDLIBS   := -lcholmod -Wl,-Bstatic -lgsl -Wl,-Bdynamic -lopenblas -linih -lgomp -lm

CORE_SRC  := $(sort $(wildcard lib/core/*.c))
CONFIG_SRC:= $(sort $(wildcard lib/config/*.c))
INSTR_SRC := $(sort $(wildcard lib/instruments/*.c))
IO_SRC    := $(sort $(wildcard lib/io/*.c))
LIB_OBJ  := $(CORE_SRC:%.c=$(BUILD)/%.o) $(CONFIG_SRC:%.c=$(BUILD)/%.o) $(INSTR_SRC:%.c=$(BUILD)/%.o) $(IO_SRC:%.c=$(BUILD)/%.o) $(BUILD)/version.o
LIB      := $(BUILD)/libclothbench.a
TOOLS    := $(BUILD)/simulate
# one program per folder experiments/<name>/ (main.c plus what serves only it)
EXP_NAMES:= $(sort $(notdir $(patsubst %/,%,$(dir $(wildcard experiments/*/main.c)))))
EXPS     := $(EXP_NAMES:%=$(BUILD)/%)
exp_obj   = $(patsubst %.c,$(BUILD)/%.o,$(sort $(wildcard experiments/$(1)/*.c)))
BENCH_SRC:= $(sort $(wildcard bench/*.c))
BENCHES  := $(BENCH_SRC:bench/%.c=$(BUILD)/%)
REPORT_SRC := $(filter-out claims/main.c,$(sort $(wildcard claims/*.c)))
REPORT_LIB := $(BUILD)/libreport.a
TEST_SRC := $(sort $(wildcard tests/test_*.c))
TESTS    := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
TEST_OBJ := $(BUILD)/tests/support.o

help:
	@sed -n 's/^##  \{0,1\}//p' $(firstword $(MAKEFILE_LIST))

.PHONY: help determinism all test check experiments run-experiments plots movies report bench san fuzz fuzz-build deps clean distclean FORCE
.DEFAULT_GOAL := all

all: $(LIB) $(TOOLS) $(EXPS) $(BENCHES) $(BUILD)/report

deps:
	@scripts/deps.sh

# ---- build -------------------------------------------------------------------

$(BUILD)/version.c: FORCE
	@scripts/version.sh $@ $(CFLAGS)

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

.SECONDEXPANSION:
$(EXPS): $(BUILD)/%: $$(call exp_obj,%) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

# every bench program links bench/support/ (the allocation counter, the triad)
BENCH_SUPPORT := $(patsubst %.c,$(BUILD)/%.o,$(wildcard bench/support/*.c))
$(BUILD)/%: $(BUILD)/bench/%.o $(BENCH_SUPPORT) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/tests/%: $(BUILD)/tests/%.o $(TEST_OBJ) $(REPORT_LIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -lcriterion -o $@

# ---- tests -------------------------------------------------------------------

# `make test` = deps, then the build and the checks in a second make, so that
# nothing compiles before the packages are there.
test: deps
	@$(MAKE) --no-print-directory check

DETERMINISM_EXP ?= linear_solvers

check: $(TESTS) $(TOOLS) $(BUILD)/$(DETERMINISM_EXP) $(BUILD)/topology $(BUILD)/definiteness $(BUILD)/nonlinear $(BUILD)/report $(EXPS)
	@scripts/check-blas.sh $(BUILD)/simulate
	@set -e; for t in $(TESTS); do echo "== $$t"; CB_QUIET=1 CB_SIMULATE=$(BUILD)/simulate $$t --jobs 2 --short-filename; done
	@BUILD=$(BUILD) tests/cli.sh
	@BUILD=$(BUILD) tests/report.sh
	@BUILD=$(BUILD) tests/lock.sh
	@BUILD=$(BUILD) tests/determinism.sh $(DETERMINISM_EXP)
	@BUILD=$(BUILD) tests/shard.sh topology 3
	@BUILD=$(BUILD) tests/shard.sh definiteness 2
	@BUILD=$(BUILD) tests/shard.sh nonlinear 2
	@BUILD=$(BUILD) tests/scripts.sh
	@BUILD=$(BUILD) tests/csv_convention.sh
	@CC="$(CC)" CPPFLAGS="$(CPPFLAGS)" CORE_INC="$(CORE_INC)" CONFIG_INC="$(CONFIG_INC)" INSTR_INC="$(INSTR_INC)" IO_INC="$(IO_INC)" tests/layers.sh
	@echo "all tests passed"

# every experiment's --quick run twice: identical CSVs apart from the date and
# the timing columns (CI runs it; make test checks linear_solvers alone)
determinism: $(EXPS)
	@set -e; for x in $(EXP_NAMES); do BUILD=$(BUILD) tests/determinism.sh $$x; done

san: deps
	@$(MAKE) --no-print-directory BUILD=build/san OPT=-O1 \
	  SAN="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" check

# ---- fuzzing: clang's libFuzzer on the config parser, the OBJ reader and scene building
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

$(BUILD)/fuzz_%: $(BUILD)/fuzz/fuzz_%.o $(LIB)
	$(CC) $(LDFLAGS) -fsanitize=fuzzer $^ $(LDLIBS) -o $@

# ---- experiments, plots, report ------------------------------------------------

EXP_ENV := OPENBLAS_NUM_THREADS=$(THREADS) OMP_NUM_THREADS=$(THREADS)
EXP_CSV := $(EXP_NAMES:%=results/%.csv)

# After a full run (not QUICK=1), the numbers in README.md and docs/experiments/
# are regenerated from the new results (build/report --fill): they are never typed.
DOC_FILL := README.md $(wildcard docs/experiments/*.md)

experiments: deps
	@$(MAKE) --no-print-directory run-experiments
	@$(MAKE) --no-print-directory plots movies report
	@tests/csv_convention.sh --results results
ifneq ($(QUICK),1)
	@$(BUILD)/report --results results --fill-only $(addprefix --fill ,$(DOC_FILL))
endif

run-experiments: $(EXPS)
	@$(MAKE) --no-print-directory $(EXP_CSV:%=%.run)

# each run records its wall time in results/<name>.runtime (for the report's run-time table)
results/%.csv.run: $(BUILD)/%
	@mkdir -p results
	@t0=$$(date +%s.%N); \
	echo "$(EXP_ENV) $(BUILD)/$* $(if $(filter 1,$(QUICK)),--quick) --out results/$*.csv"; \
	$(EXP_ENV) $(BUILD)/$* $(if $(filter 1,$(QUICK)),--quick) --out results/$*.csv || exit $$?; \
	t1=$$(date +%s.%N); \
	awk -v a=$$t0 -v b=$$t1 -v q=$(QUICK) 'BEGIN { printf "wall_s: %.1f\nquick: %d\n", b - a, q == 1 }' > results/$*.runtime

plots:
	@scripts/plots.sh

# animated GIFs of paired runs (scripts/movies.sh lists them); the report embeds them
movies: deps $(TOOLS)
	@BUILD=$(BUILD) scripts/movies.sh

# the report program is a prerequisite (built under this make's jobserver), so
# scripts/report.sh does not call make itself
report: $(BUILD)/report
	@BUILD=$(BUILD) scripts/report.sh

# Debian's python3 (its python3-scipy), whatever python3 the PATH finds first
PYTHON ?= /usr/bin/python3

bench: deps
	@scripts/deps.sh python3-scipy
	@$(MAKE) --no-print-directory $(BENCHES)
	@mkdir -p results
	@rm -f $(BUILD)/bench_matrix_*.bin
	$(EXP_ENV) CB_BENCH_MATRIX_DIR=$(BUILD) $(BUILD)/bench_core $(if $(filter 1,$(QUICK)),--quick) --out results/bench_core.csv
	$(EXP_ENV) $(PYTHON) bench/spmv_scipy.py $(BUILD)/bench_spmv $(BUILD) results/bench_scipy.csv
	$(PYTHON) scripts/readme-perf.py results README.md
	$(EXP_ENV) $(BUILD)/bench_nonlinear --out results/bench_nonlinear.csv
	$(PYTHON) scripts/readme-bench-nonlinear.py results README.md

clean:
	rm -rf build

distclean: clean
	rm -rf results plots/out

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
.SECONDARY:
