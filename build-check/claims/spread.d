build-check/claims/spread.o: claims/spread.c claims/claims.h \
 lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
