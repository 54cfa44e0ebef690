#!/usr/bin/env python3
"""Where and how a diverging cavity job's flow breaks down, from its particle snapshots.

For each of the last N snapshots (default 30) of a job folder (particles/*.vtp, written with
output_interval > 0, which is not part of the job key: a rerun with it is the same job), one CSV
row: the time t; the fastest fluid particle (v_max, its x, y and id); the smallest fluid-fluid
nearest-neighbour distance (nn_min, at nn_x, nn_y); the count of fluid particles closer than
0.6 dx to another (n_close); the smallest fluid-to-wall-particle distance (wall_min); the spread
of the fluid pressure (p_spread, max - min). Enough to tell a particle that accelerates along a
wall from a pair that collapses or a particle that leaks into the wall.

    scripts/isph_divergence_track.py JOB_DIR DX [N]

Distances are in units of DX (the job's dx). Needs numpy only.
"""
import sys

import numpy as np
from snapshots import read_vtp, snapshot_files


def nearest(a, b, same):
    """Distance from each point of a to its nearest point of b (itself excluded when same)."""
    out = np.empty(len(a))
    for s in range(0, len(a), 512):
        d = np.linalg.norm(a[s:s + 512, None, :] - b[None, :, :], axis=2)
        if same:
            d[np.arange(d.shape[0]), np.arange(s, s + d.shape[0])] = np.inf
        out[s:s + 512] = d.min(axis=1)
    return out


def main(argv):
    if len(argv) < 2 or argv[0].startswith("-"):
        sys.exit(__doc__)
    job, dx = argv[0], float(argv[1])
    n = int(argv[2]) if len(argv) > 2 else 30
    files = snapshot_files(job)
    if not files:
        sys.exit(f"{job}: no particles/*.vtp (run the job with output_interval > 0)")
    print("t,v_max,x,y,id,nn_min,nn_x,nn_y,n_close,wall_min,p_spread")
    for f in files[-n:]:
        s = read_vtp(f, {"Points", "velocity", "kind", "pressure", "id"})
        fl = s["kind"] == 0
        x, v = s["Points"][fl, :2], s["velocity"][fl, :2]
        sp = np.linalg.norm(v, axis=1)
        i = int(np.argmax(sp))
        nn = nearest(x, x, True) / dx
        j = int(np.argmin(nn))
        dw = nearest(x, s["Points"][~fl, :2], False) / dx
        p = s["pressure"][fl]
        print(f"{s['t']:.3f},{sp[i]:.3f},{x[i, 0]:.3f},{x[i, 1]:.3f},{s['id'][fl][i]},"
              f"{nn[j]:.3f},{x[j, 0]:.3f},{x[j, 1]:.3f},{int(np.sum(nn < 0.6))},"
              f"{dw.min():.3f},{p.max() - p.min():.3g}")


if __name__ == "__main__":
    main(sys.argv[1:])
