build-check/lib/core/definiteness.o: lib/core/definiteness.c \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/status.h
include/clothbench/definiteness.h:
include/clothbench/projection.h:
include/clothbench/status.h:
