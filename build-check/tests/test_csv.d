build-check/tests/test_csv.o: tests/test_csv.c include/clothbench/csv.h
include/clothbench/csv.h:
