build-check/lib/instruments/pareto.o: lib/instruments/pareto.c \
 lib/instruments/pareto.h
lib/instruments/pareto.h:
