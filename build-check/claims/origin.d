build-check/claims/origin.o: claims/origin.c claims/claims.h \
 lib/instruments/stats.h claims/table.h claims/report.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
claims/report.h:
