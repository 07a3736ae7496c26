"""Geometry of the MPI scaling model (studies/scaling/scaling_model.py, docs/scaling.md) against
cases with known answers. Every comparison is exact (integers): the model counts nodes and points,
so any difference is a bug, not round-off. Runs in about a second."""

import os
import sys

import numpy as np
import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
sys.path.insert(0, os.path.join(ROOT, "studies", "scaling"))

import scaling_model as sm  # noqa: E402


@pytest.mark.parametrize("bits", [1, 2, 3])
def test_hilbert_keys_are_a_face_connected_permutation(bits):
    n = 1 << bits
    g = np.stack(np.meshgrid(*(np.arange(n),) * 3, indexing="ij"), -1).reshape(-1, 3)
    k = sm.hilbert_key(g, bits)
    assert sorted(k.tolist()) == list(range(n**3))
    steps = np.abs(np.diff(g[np.argsort(k)], axis=0)).sum(axis=1)
    assert np.all(steps == 1)  # consecutive Hilbert cells share a face


@pytest.mark.parametrize("curve", ["morton", "hilbert"])
@pytest.mark.parametrize("n_blocks", [4, 8])
@pytest.mark.parametrize("parts", [2, 8])
def test_cube_halo_is_cut_area_times_stencil_depth(curve, n_blocks, parts):
    """A cube of n^3 full blocks cut into 2 halves or 8 octants (both curves cut a 2^k cube so):
    the halo is the 2 node layers either side of each cut plane reaches, over the stencil
    footprint of 4n + 2 nodes per axis (sm.cube_halo_expected: 2 (4n+2)^2 for halves,
    (4n+4)^3 - (4n+2)^3 for octants). Directed neighbour pairs: 1 for halves; 19 for octants
    (stencils reach only +{0,1}^3, so octant (i,j,k) sends to those above it on every axis
    where it is low: sum over octants of 2^(low axes) - 1)."""
    g = sm.uniform_cube(n_blocks)
    top = sm.topology(g)
    own, _ = sm.decompose(top, parts, curve)
    h = sm.halo(top, own, parts)
    assert np.all(h.particles == g.particles / parts)
    assert int(h.pair_nodes.sum()) == sm.cube_halo_expected(n_blocks, parts)
    assert len(h.pair_src) == {2: 1, 8: 19}[parts]


@pytest.mark.parametrize("curve", ["morton", "hilbert"])
@pytest.mark.parametrize("ranks", [3, 7, 16])
def test_block_class_halo_equals_node_by_node_count(curve, ranks):
    """The vectorised per-class count against a node-by-node enumeration on the asteroid scene
    at 1000 m cells (145 occupied blocks, partly filled ones at the surface), reached-only
    blocks owned by the reacher rule."""
    g = sm.asteroid_initial(1000.0)
    top = sm.topology(g)
    own, _ = sm.decompose(top, ranks, curve)
    h = sm.halo(top, own, ranks)
    fast = {(int(a), int(b)): int(c) for a, b, c in zip(h.pair_src, h.pair_dst, h.pair_nodes)}
    assert fast == sm.brute_force_halo(g, own, ranks)


@pytest.mark.parametrize("cell, target, projectile", [(1000.0, 32876, 80), (500.0, 261992, 604)])
def test_point_counts_match_the_engine(cell, target, projectile):
    """Points per body as `shatter run scenes/asteroid-collision.toml --set solver.cell_size=...`
    reports them (500 m: docs/validation-asteroid.md Sec. 1; 1000 m: the run docs/scaling.md
    uses for the debris)."""
    _, wt = sm.sphere_block_counts((0, 0, 0), sm.R_TARGET, cell, sm.DOMAIN_LO)
    _, wp = sm.sphere_block_counts(sm.PROJ_CENTRE, sm.R_PROJ, cell, sm.DOMAIN_LO)
    assert (wt.sum(), wp.sum()) == (target, projectile)


@pytest.mark.parametrize("rule", ["midpoint", "prefix"])
def test_equal_weight_cut_is_within_one_block(rule):
    g = sm.asteroid_initial(500.0)
    top = sm.topology(g)
    for ranks in (5, 64):
        own, _ = sm.decompose(top, ranks, "morton", rule=rule)
        per = np.bincount(own, weights=g.weight, minlength=ranks)
        assert per.sum() == g.particles
        assert np.max(np.abs(per - g.particles / ranks)) <= g.weight.max()


def test_block_counts_equal_point_by_point_owner_blocks():
    """sphere_block_counts against every lattice point of the target at 1000 m cells put in the
    block of its stencil's first node one by one (sm.owner_block)."""
    cell = 1000.0
    lo = sm.DOMAIN_LO
    j = np.arange(int((sm.DOMAIN_HI[0] - lo[0]) / cell * sm.PPC))
    x1 = lo[0] + (j + 0.5) * cell / sm.PPC
    z1 = lo[2] + (j + 0.5) * cell / sm.PPC
    x1 = x1[np.abs(x1) < sm.R_TARGET + cell]
    z1 = z1[(z1 > 0) & (z1 < sm.R_TARGET + cell)]
    p = np.stack(np.meshgrid(x1, x1, z1, indexing="ij"), -1).reshape(-1, 3)
    p = p[np.sum(p**2, axis=1) < sm.R_TARGET**2]
    b, n = np.unique(sm.owner_block(p, cell, lo), axis=0, return_counts=True)
    c, w = sm.sphere_block_counts((0, 0, 0), sm.R_TARGET, cell, lo)
    order = np.lexsort(c.T[::-1])
    assert np.array_equal(c[order], b) and np.array_equal(w[order], n)


@pytest.mark.parametrize("curve", ["morton", "hilbert"])
@pytest.mark.parametrize("ranks", [4, 16])
def test_interval_rule_equals_node_by_node_count(curve, ranks):
    """With reached-only blocks owned by the rank whose curve interval holds their key (the
    mpi helper's Decomposition::rank_of), the vectorised count against the node-by-node one."""
    g = sm.asteroid_initial(1000.0)
    top = sm.topology(g)
    own, starts = sm.decompose(top, ranks, curve)
    alloc = sm.alloc_owner_by_interval(top, curve, starts)
    h = sm.halo(top, own, ranks, alloc)
    lookup = {tuple(int(x) for x in b): int(r) for b, r in zip(top.alloc, alloc)}
    fast = {(int(a), int(b)): int(c) for a, b, c in zip(h.pair_src, h.pair_dst, h.pair_nodes)}
    assert fast == sm.brute_force_halo(g, own, ranks, lambda bc: lookup[bc])
