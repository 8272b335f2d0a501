build-check/tests/test_claims_topology.o: tests/test_claims_topology.c \
 claims/claims.h lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
