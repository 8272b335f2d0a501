build-check/lib/instruments/rigidity.o: lib/instruments/rigidity.c \
 lib/instruments/rigidity.h include/clothbench/mesh.h \
 include/clothbench/status.h
lib/instruments/rigidity.h:
include/clothbench/mesh.h:
include/clothbench/status.h:
