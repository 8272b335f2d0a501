build-check/tests/test_claims_locking.o: tests/test_claims_locking.c \
 claims/claims.h lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
