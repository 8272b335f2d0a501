build-check/lib/io/outfile.o: lib/io/outfile.c lib/io/outfile.h \
 include/clothbench/mesh.h include/clothbench/status.h
lib/io/outfile.h:
include/clothbench/mesh.h:
include/clothbench/status.h:
