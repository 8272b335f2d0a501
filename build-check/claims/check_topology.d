build-check/claims/check_topology.o: claims/check_topology.c \
 claims/claims.h lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
