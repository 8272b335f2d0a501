"""What the SciPy sides of make bench share (bench/spmv_scipy.py, bench/peers_scipy.py): the Newton matrices
bench_core exports (CB_BENCH_MATRIX_DIR; the format: bench/bench_core.c), the median/min/max of samples, and the
output CSV with its provenance."""
import glob
import os
import re
import sys
import time

import numpy as np
import scipy


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


def write_csv(out, prog, hdr, rows, before=(), after=()):
    """Writes out (atomically, through a temporary file): the provenance lines '# program: bench/PROG.py', python,
    scipy and numpy, then the lines before, the command and the date, the lines after (each line without its
    newline), then hdr and rows; and says so on stderr."""
    head = [f"# program: bench/{prog}.py", f"# python: {sys.version.split()[0]}", f"# scipy: {scipy.__version__}",
            f"# numpy: {np.__version__}", *before, f"# command: {' '.join(sys.argv)}",
            f"# date: {time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())}", *after, hdr]
    tmp = out + ".tmp." + str(os.getpid())
    with open(tmp, "w") as f:
        f.write("\n".join(head) + "\n")
        f.write("\n".join(rows) + "\n")
    os.replace(tmp, out)
    print(f"{prog}: wrote {out}", file=sys.stderr)
