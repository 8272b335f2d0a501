build-check/tests/test_claims_bending.o: tests/test_claims_bending.c \
 claims/claims.h lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
