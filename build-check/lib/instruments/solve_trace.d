build-check/lib/instruments/solve_trace.o: lib/instruments/solve_trace.c \
 lib/instruments/solve_trace.h include/clothbench/solver.h \
 include/clothbench/sparse.h include/clothbench/sparse.h \
 include/clothbench/status.h include/clothbench/timer.h
lib/instruments/solve_trace.h:
include/clothbench/solver.h:
include/clothbench/sparse.h:
include/clothbench/sparse.h:
include/clothbench/status.h:
include/clothbench/timer.h:
