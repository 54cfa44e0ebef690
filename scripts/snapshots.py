"""Reading the particle snapshots a job writes (particles/*.vtp, solver/io/particle_snapshot.cpp:
VTK PolyData with raw appended arrays, each a UInt64 byte count and then the data), with numpy
only; shared by the analysis scripts beside it (run as scripts, their folder is on sys.path)."""
import glob
import os
import re

import numpy as np

TYPES = {"Float64": np.float64, "UInt8": np.uint8, "Int64": np.int64}


def read_vtp(path, names):
    """The named point arrays of one raw-appended VTK PolyData snapshot (solver/io/
    particle_snapshot.cpp writes them: UInt64 byte count, then the data)."""
    b = open(path, "rb").read()
    k = b.index(b'<AppendedData encoding="raw">')
    head = b[:k].decode()
    base = b.index(b"_", k) + 1
    out = {"t": float(re.search(r'Name="TimeValue"[^>]*>([^<]*)<', head).group(1))}
    pat = r'<DataArray type="(\w+)" Name="([^"]+)" NumberOfComponents="(\d+)" format="appended" offset="(\d+)"'
    for m in re.finditer(pat, head):
        ty, name, nc, off = m.group(1), m.group(2), int(m.group(3)), int(m.group(4))
        if name in names:
            o = base + off
            n = int(np.frombuffer(b[o:o + 8], np.uint64)[0])
            a = np.frombuffer(b[o + 8:o + 8 + n], TYPES[ty])
            out[name] = a.reshape(-1, nc) if nc > 1 else a
    return out


def snapshot_files(job):
    """A job folder's snapshots in time order (particles/particles_NNNNNN.vtp)."""
    return sorted(glob.glob(os.path.join(job, "particles", "particles_*.vtp")))
