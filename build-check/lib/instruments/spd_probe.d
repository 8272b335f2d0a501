build-check/lib/instruments/spd_probe.o: lib/instruments/spd_probe.c \
 lib/instruments/spd_probe.h include/clothbench/eigen.h \
 include/clothbench/sparse.h include/clothbench/solver.h \
 include/clothbench/sparse.h include/clothbench/status.h \
 include/clothbench/timer.h
lib/instruments/spd_probe.h:
include/clothbench/eigen.h:
include/clothbench/sparse.h:
include/clothbench/solver.h:
include/clothbench/sparse.h:
include/clothbench/status.h:
include/clothbench/timer.h:
