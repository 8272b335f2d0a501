build-check/tests/test_claims_definiteness.o: \
 tests/test_claims_definiteness.c claims/claims.h lib/instruments/stats.h \
 claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
