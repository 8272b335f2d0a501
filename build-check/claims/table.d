build-check/claims/table.o: claims/table.c claims/table.h \
 include/clothbench/status.h
claims/table.h:
include/clothbench/status.h:
