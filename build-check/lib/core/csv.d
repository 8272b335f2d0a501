build-check/lib/core/csv.o: lib/core/csv.c include/clothbench/csv.h
include/clothbench/csv.h:
