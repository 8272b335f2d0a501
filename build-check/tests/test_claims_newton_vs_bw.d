build-check/tests/test_claims_newton_vs_bw.o: \
 tests/test_claims_newton_vs_bw.c claims/claims.h lib/instruments/stats.h \
 claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
