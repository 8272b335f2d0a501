# clothbench — see README.md.
#
#   make test          install missing Debian packages, build, run the tests
#   make experiments   install missing packages, run every experiment, plots, report
#   knobs: WERROR=1 (warnings are errors), QUICK=1 (reduced sweeps),
#          THREADS=n (threads of OpenBLAS and of CHOLMOD's OpenMP regions, for
#          experiments and bench; default 1)

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
CPPFLAGS := -D_POSIX_C_SOURCE=200809L -Ilib -Iclaims -I/usr/include/suitesparse $(if $(OPENBLAS_INC),-I$(OPENBLAS_INC))
CFLAGS   := $(OPT) -g $(WARN) $(SAN)
LDFLAGS  := $(SAN)
# GSL is linked statically: Debian's libgsl.so pulls in libgslcblas, and we
# link exactly one CBLAS, OpenBLAS (scripts/check-blas.sh verifies it).
LDLIBS   := -lcholmod -Wl,-Bstatic -lgsl -Wl,-Bdynamic -lopenblas -linih -lgomp -lm

LIB_SRC  := $(sort $(wildcard lib/*.c))
LIB_OBJ  := $(LIB_SRC:%.c=$(BUILD)/%.o) $(BUILD)/version.o
LIB      := $(BUILD)/libclothbench.a
TOOLS    := $(BUILD)/simulate
EXP_SRC  := $(sort $(wildcard experiments/*.c))
EXPS     := $(EXP_SRC:experiments/%.c=$(BUILD)/%)
BENCH_SRC:= $(sort $(wildcard bench/*.c))
BENCHES  := $(BENCH_SRC:bench/%.c=$(BUILD)/%)
REPORT_SRC := $(filter-out claims/main.c,$(sort $(wildcard claims/*.c)))
REPORT_LIB := $(BUILD)/libreport.a
TEST_SRC := $(sort $(wildcard tests/test_*.c))
TESTS    := $(TEST_SRC:tests/%.c=$(BUILD)/tests/%)
TEST_OBJ := $(BUILD)/tests/support.o

.PHONY: all test check experiments run-experiments plots report bench san deps clean distclean FORCE
.DEFAULT_GOAL := all

all: $(LIB) $(TOOLS) $(EXPS) $(BENCHES) $(BUILD)/report

deps:
	@scripts/deps.sh

# ---- build -------------------------------------------------------------------

$(BUILD)/version.c: FORCE
	@scripts/version.sh $@ $(CFLAGS)

$(BUILD)/%.o: %.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/version.o: $(BUILD)/version.c
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@

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

$(BUILD)/%: $(BUILD)/experiments/%.o $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/%: $(BUILD)/bench/%.o $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -o $@

$(BUILD)/tests/support.o: tests/support.c
	@mkdir -p $(dir $@)
	$(CC) $(CPPFLAGS) $(CFLAGS) -MMD -MP -c $< -o $@

$(BUILD)/tests/%: $(BUILD)/tests/%.o $(TEST_OBJ) $(REPORT_LIB) $(LIB)
	$(CC) $(LDFLAGS) $^ $(LDLIBS) -lcriterion -o $@

# ---- tests -------------------------------------------------------------------

# `make test` = deps, then the build and the checks in a second make, so that
# nothing compiles before the packages are there.
test: deps
	@$(MAKE) --no-print-directory check

DETERMINISM_EXP ?= linear_solvers

check: $(TESTS) $(TOOLS) $(BUILD)/$(DETERMINISM_EXP)
	@scripts/check-blas.sh $(BUILD)/simulate
	@set -e; for t in $(TESTS); do echo "== $$t"; CB_QUIET=1 CB_SIMULATE=$(BUILD)/simulate $$t --jobs 2 --short-filename; done
	@BUILD=$(BUILD) tests/cli.sh
	@BUILD=$(BUILD) tests/determinism.sh $(DETERMINISM_EXP)
	@echo "all tests passed"

san: deps
	@$(MAKE) --no-print-directory BUILD=build/san OPT=-O1 \
	  SAN="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined" check

# ---- experiments, plots, report ------------------------------------------------

EXP_ENV := OPENBLAS_NUM_THREADS=$(THREADS) OMP_NUM_THREADS=$(THREADS)
EXP_CSV := $(EXP_SRC:experiments/%.c=results/%.csv)

experiments: deps
	@$(MAKE) --no-print-directory run-experiments
	@$(MAKE) --no-print-directory plots report

run-experiments: $(EXPS)
	@$(MAKE) --no-print-directory $(EXP_CSV:%=%.run)

results/%.csv.run: $(BUILD)/%
	$(EXP_ENV) $(BUILD)/$* $(if $(filter 1,$(QUICK)),--quick) --out results/$*.csv

plots:
	@scripts/plots.sh

report:
	@scripts/report.sh

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

clean:
	rm -rf build

distclean: clean
	rm -rf results plots/out

-include $(shell find $(BUILD) -name '*.d' 2>/dev/null)
.SECONDARY:
