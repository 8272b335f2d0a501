build-check/lib/core/solver_shift.o: lib/core/solver_shift.c \
 include/clothbench/solver_shift.h include/clothbench/solver.h \
 include/clothbench/sparse.h include/clothbench/status.h
include/clothbench/solver_shift.h:
include/clothbench/solver.h:
include/clothbench/sparse.h:
include/clothbench/status.h:
