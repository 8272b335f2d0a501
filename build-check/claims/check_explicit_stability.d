build-check/claims/check_explicit_stability.o: \
 claims/check_explicit_stability.c claims/claims.h \
 lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
