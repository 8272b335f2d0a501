build-check/lib/core/polar.o: lib/core/polar.c include/clothbench/polar.h
include/clothbench/polar.h:
