build-check/tests/test_pareto.o: tests/test_pareto.c \
 lib/instruments/pareto.h
lib/instruments/pareto.h:
