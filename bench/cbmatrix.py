"""What the SciPy sides of make bench share (bench/spmv_scipy.py, bench/peers_scipy.py): the Newton matrices
bench_core exports (CB_BENCH_MATRIX_DIR; the format: bench/bench_core.c) and the median/min/max of samples."""
import glob
import os
import re
import sys

import numpy as np


def matrix_files(mdir):
    """{n: path} of the bench_matrix_<n>.bin files in mdir (the matrix at n^2 vertices)."""
    return {int(re.search(r"_(\d+)\.bin$", f).group(1)): f for f in glob.glob(os.path.join(mdir, "bench_matrix_*.bin"))}


def read_matrix(path, prog):
    """(dofs, nnz, indptr, indices, data) of the CSR matrix in path (int32 dofs and nnz, int32 indptr[dofs + 1],
    int32 indices[nnz], float64 data[nnz]), or None (with prog's message on stderr) when the file is short."""
    with open(path, "rb") as f:
        dofs, nnz = np.fromfile(f, dtype=np.int32, count=2)
        indptr = np.fromfile(f, dtype=np.int32, count=dofs + 1)
        indices = np.fromfile(f, dtype=np.int32, count=nnz)
        data = np.fromfile(f, dtype=np.float64, count=nnz)
    if len(data) != nnz:
        sys.stderr.write(f"{prog}: {path}: short file\n")
        return None
    return dofs, nnz, indptr, indices, data


def stats(v):
    """(median, min, max) of the samples v."""
    return float(np.median(v)), float(np.min(v)), float(np.max(v))
