build-check/tests/test_claims_field.o: tests/test_claims_field.c \
 claims/claims.h lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
