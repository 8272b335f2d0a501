build-check/tests/test_stats.o: tests/test_stats.c \
 lib/instruments/stats.h
lib/instruments/stats.h:
