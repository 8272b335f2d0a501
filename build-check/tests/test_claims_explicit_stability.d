build-check/tests/test_claims_explicit_stability.o: \
 tests/test_claims_explicit_stability.c claims/claims.h \
 lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
