build-check/lib/instruments/spectrum.o: lib/instruments/spectrum.c \
 lib/instruments/spectrum.h include/clothbench/sparse.h \
 include/clothbench/eigen.h include/clothbench/sparse.h \
 include/clothbench/solver.h include/clothbench/status.h \
 include/clothbench/timer.h
lib/instruments/spectrum.h:
include/clothbench/sparse.h:
include/clothbench/eigen.h:
include/clothbench/sparse.h:
include/clothbench/solver.h:
include/clothbench/status.h:
include/clothbench/timer.h:
