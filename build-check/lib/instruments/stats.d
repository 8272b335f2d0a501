build-check/lib/instruments/stats.o: lib/instruments/stats.c \
 lib/instruments/stats.h include/clothbench/csv.h
lib/instruments/stats.h:
include/clothbench/csv.h:
