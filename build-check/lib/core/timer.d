build-check/lib/core/timer.o: lib/core/timer.c include/clothbench/timer.h
include/clothbench/timer.h:
