build-check/claims/main.o: claims/main.c claims/claims.h \
 lib/instruments/stats.h claims/table.h claims/report.h lib/io/outfile.h \
 include/clothbench/mesh.h lib/io/provenance.h lib/config/config.h \
 include/clothbench/status.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
claims/report.h:
lib/io/outfile.h:
include/clothbench/mesh.h:
lib/io/provenance.h:
lib/config/config.h:
include/clothbench/status.h:
