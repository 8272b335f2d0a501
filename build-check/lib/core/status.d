build-check/lib/core/status.o: lib/core/status.c \
 include/clothbench/status.h
include/clothbench/status.h:
