build-check/tests/test_claims_nonlinear.o: tests/test_claims_nonlinear.c \
 claims/claims.h lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
