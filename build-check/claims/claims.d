build-check/claims/claims.o: claims/claims.c claims/claims.h \
 lib/instruments/stats.h claims/table.h include/clothbench/status.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
include/clothbench/status.h:
