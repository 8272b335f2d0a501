"""What the README generators share (scripts/readme-perf.py, scripts/readme-peers.py): reading a bench CSV with
its provenance, the number formats, and writing a generated block between its markers in README.md."""
import csv
import os
import sys


def load(path):
    """(provenance dict, rows) of a CSV with '# key: value' lines."""
    prov, lines = {}, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                k, _, v = line[1:].strip().partition(": ")
                prov.setdefault(k, v)
            elif line.strip():
                lines.append(line)
    return prov, list(csv.DictReader(lines))


def ms(v):
    """A time in ms (a number or its CSV text) to 3 or 4 significant figures, fewer at 100 and above."""
    v = float(v)
    if v >= 100:
        return f"{v:.0f}"
    if v >= 10:
        return f"{v:.1f}"
    if v >= 1:
        return f"{v:.2f}"
    return f"{v:.3f}"


def kernel(prov):
    """The OpenBLAS kernel of a run and how it came to run (its provenance)."""
    return f"{prov.get('blas_kernel', '?')} ({prov.get('blas_kernel_choice', 'not recorded')})"


def rule(header):
    """The |---|...| line under a table's header row, one cell per column."""
    return "|" + "---|" * (header.count("|") - 1)


def write_block(readme, name, text, prog):
    """Replaces what stands between README's <!-- name:begin --> and <!-- name:end --> markers with text (atomically,
    through a temporary file); returns 0, or 1 (with prog's message on stderr) when the markers are missing."""
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    with open(readme) as f:
        src = f.read()
    if begin not in src or end not in src:
        sys.stderr.write(f"{prog}: {readme} lacks the {begin} / {end} markers\n")
        return 1
    head, rest = src.split(begin, 1)
    _, tail = rest.split(end, 1)
    tmp = readme + ".tmp." + str(os.getpid())
    with open(tmp, "w") as f:
        f.write(head + begin + "\n" + text + end + tail)
    os.replace(tmp, readme)
    return 0
