#!/usr/bin/env python3
"""Independent reference for Laplacian mesh editing with hard constraints.

Usage: laplacian_reference.py DIR

Reads from DIR
  positions.txt  n rows "x y z"
  triangles.txt  m rows "i j k"
  handles.txt    rows "index x y z" (may be empty)
  fixed.txt      vertex indices (may be empty)
  roi.txt        vertex indices, empty for the whole mesh
  weights.txt    "uniform" or "cotangent"
and writes DIR/result.txt (n rows "x y z").

It minimizes ||L V' - delta||^2 with delta = L V over all vertices, subject to
V'_c = U_c for handles, fixed vertices and every vertex outside the region of
interest, by solving the full KKT system with SuperLU (scipy.sparse.linalg.spsolve):
    [ L^T L   C^T ] [V']   [ L^T delta ]
    [ C       0   ] [mu] = [ U         ]
No elimination, no row selection: a different route from the engine's.
"""
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def load(directory, name, dtype=float, ndmin=2, empty_shape=(0,)):
    path = os.path.join(directory, name)
    if os.path.getsize(path) == 0:
        return np.zeros((0,) + empty_shape, dtype=dtype)
    return np.loadtxt(path, dtype=dtype, ndmin=ndmin)


def weight_matrix(V, F, kind):
    n = len(V)
    if kind == "uniform":
        rows = np.concatenate([F[:, 0], F[:, 1], F[:, 2], F[:, 1], F[:, 2], F[:, 0]])
        cols = np.concatenate([F[:, 1], F[:, 2], F[:, 0], F[:, 0], F[:, 1], F[:, 2]])
        W = sp.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n)).tocsr()
        W.data[:] = 1.0  # an edge shared by two triangles counts once
        return W
    rows, cols, vals = [], [], []
    for corner in range(3):
        o, i, j = F[:, corner], F[:, (corner + 1) % 3], F[:, (corner + 2) % 3]
        u, v = V[i] - V[o], V[j] - V[o]
        cot = np.einsum("ij,ij->i", u, v) / np.linalg.norm(np.cross(u, v), axis=1)
        rows += [i, j]
        cols += [j, i]
        vals += [cot / 2, cot / 2]
    return sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)).tocsr()


def main(directory):
    V = load(directory, "positions.txt")
    F = load(directory, "triangles.txt", dtype=np.int64)
    handles = load(directory, "handles.txt", empty_shape=(4,))
    fixed = load(directory, "fixed.txt", dtype=np.int64, ndmin=1, empty_shape=())
    roi = load(directory, "roi.txt", dtype=np.int64, ndmin=1, empty_shape=())
    kind = open(os.path.join(directory, "weights.txt")).read().strip()
    n = len(V)

    W = weight_matrix(V, F, kind)
    degree = np.asarray(W.sum(axis=1)).ravel()
    L = sp.identity(n, format="csr") - sp.diags(1.0 / degree) @ W
    delta = L @ V

    target = {}
    if len(roi):
        outside = np.ones(n, dtype=bool)
        outside[roi.astype(np.int64)] = False
        for v in np.nonzero(outside)[0]:
            target[int(v)] = V[v]
    for v in fixed:
        target[int(v)] = V[int(v)]
    for row in handles:
        target[int(row[0])] = row[1:4]
    constrained = np.array(sorted(target), dtype=np.int64)
    k = len(constrained)
    C = sp.coo_matrix((np.ones(k), (np.arange(k), constrained)), shape=(k, n))
    U = np.array([target[int(v)] for v in constrained]).reshape(k, 3)

    LtL = (L.T @ L).tocsc()
    kkt = sp.bmat([[LtL, C.T], [C, None]], format="csc")
    rhs = np.vstack([L.T @ delta, U])
    solution = spla.spsolve(kkt, rhs)
    np.savetxt(os.path.join(directory, "result.txt"), solution[:n], fmt="%.17g")


if __name__ == "__main__":
    main(sys.argv[1])
