build-check/claims/fill.o: claims/fill.c include/clothbench/status.h \
 lib/io/outfile.h include/clothbench/mesh.h claims/report.h \
 claims/claims.h lib/instruments/stats.h claims/table.h
include/clothbench/status.h:
lib/io/outfile.h:
include/clothbench/mesh.h:
claims/report.h:
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
