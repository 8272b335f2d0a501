build-check/claims/check_locking.o: claims/check_locking.c \
 claims/claims.h lib/instruments/stats.h claims/table.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
