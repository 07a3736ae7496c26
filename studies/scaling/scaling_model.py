#!/usr/bin/python3
"""Performance model of shatter's MPI domain decomposition (issue 15, "Scaling evidence").

Predicts strong and weak scaling from 1 to 1024 ranks for the asteroid collision
(scenes/asteroid-collision.toml, half model, 2 x 2 x 2 points per cell) from
  * compute per particle-step measured on this project's machine (docs/performance.md,
    docs/validation-asteroid.md),
  * the halo of the decomposition the `mpi` helper builds: 4x4x4-node blocks, blocks cut into
    contiguous chunks of equal particle weight along a space-filling curve (Morton or Hilbert
    over block coordinates), partial node sums sent to each node's owner and the final values
    returned (P2G scatter 7 doubles per node, return 6, MUSL remap scatter 4, return 3), one
    message per neighbour rank and phase, particle migration, allreduces,
  * a latency-bandwidth (alpha-beta) network model with stated parameters.

The geometry works per block (particles counted per block, never one by one), so 1e8-1e9 points
take seconds. docs/scaling.md explains every assumption and shows the results.

    studies/scaling/scaling_model.py                       # tables to stdout, figures into docs/figures
    studies/scaling/scaling_model.py --quick               # no 1e9-point weak scaling (~15 s)
    studies/scaling/scaling_model.py --debris RUN --drift RUN2 --tables T.md
        # also the debris cloud of a coarse run (snapshots up to 100 s) and the drift between
        # recuts (snapshots every 0.5 s); docs/scaling.md gives the two run commands

Halo geometry of one block (docs/architecture.md, Grid): a particle's stencil is 3 nodes wide
and starts in its owner block, so an occupied block B reaches all 64 nodes of B and, of the
neighbour block B + o (o in {0,1}^3), the nodes whose local index is 0 or 1 along every axis
where o is 1. Nodes of a block therefore fall into 8 classes c in {0,1}^3 (c_a = 1: local index
0-1 along axis a, 8 nodes each), and the occupied blocks reaching class c of block B are B - o
for every o <= c. A node is a halo node for every reaching rank other than its owner: that rank
sends its partial sums there and gets the final values back.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]

# ---------------------------------------------------------------------------------------------
# Stated parameters (docs/scaling.md, "Assumptions", says where each comes from)
# ---------------------------------------------------------------------------------------------


@dataclass
class Params:
    # Compute: CPU ns per particle-step, one core. 525 ns = docs/validation-asteroid.md, case a1
    # at 500 m (121 s CPU / (877 steps x 262 596 points), full physics, output included).
    t_particle_ns: float = 525.0
    # Grid work per extra node a rank allocates for nodes it reaches in other ranks' blocks:
    # grid_update in bench/baseline.json, 118 us per 1e5 particles at ~0.2 nodes per particle.
    t_node_ns: float = 6.0
    # Packing/unpacking halo buffers: read + write at one core's stream rate (~17 GB/s,
    # docs/performance.md, elastic update).
    copy_bandwidth: float = 17e9 / 2
    # Doubles per halo node per step: P2G scatter (mass, momentum, force), its return
    # (velocity, acceleration), MUSL remap scatter, its return (the mpi helper's design).
    phase_doubles: tuple = (7, 6, 4, 3)
    # Bytes per migrating particle: 44 double columns + id + body of the asteroid scene's
    # checkpoint (Tillotson + linear hardening + Grady-Kipp, 1000 m run), plus the group index
    # the mpi helper's pack_particles puts in front of each row.
    migrant_bytes: float = 47 * 8
    # Fraction of a cell a boundary particle crosses per step: cfl * v / (c + v), with v the
    # 99th percentile speed of the coarse run (~500 m/s) and c = 4.4 km/s.
    migrate_fraction: float = 0.3 * 500.0 / 4900.0
    allreduces_per_step: int = 3  # dt (min), energy sums, failure ratio
    ranks_per_node: int = 64
    # Inter-node: EDR/HDR InfiniBand, MPI level. alpha: 0.9-1.7 us measured small-message
    # latency (OpenMPI ping-pong), 1.2 us RDMA latency (Azure HBv3, HDR); beta: EDR 100 Gb/s,
    # ~10.3 GB/s reached by MPI at 32 KiB messages. One NIC per node, shared by its ranks.
    alpha_net: float = 1.5e-6
    beta_net: float = 12e9
    # Intra-node shared memory: copy in and out through a shared segment (4 memory passes at
    # ~17 GB/s -> ~4 GB/s per rank pair); alpha a typical intra-node MPI latency.
    alpha_shm: float = 0.5e-6
    beta_shm: float = 4e9


# ---------------------------------------------------------------------------------------------
# Space-filling curves over block coordinates
# ---------------------------------------------------------------------------------------------


def morton_key(c: np.ndarray, bits: int) -> np.ndarray:
    """Morton (Z-order) key of integer coordinates c (n, 3), bits per axis; x most significant
    within each bit triple."""
    c = c.astype(np.int64)
    key = np.zeros(len(c), dtype=np.int64)
    for b in range(bits - 1, -1, -1):
        for a in range(3):
            key = (key << 1) | ((c[:, a] >> b) & 1)
    return key


def hilbert_key(c: np.ndarray, bits: int) -> np.ndarray:
    """Hilbert key of integer coordinates c (n, 3): J. Skilling, "Programming the Hilbert
    curve", AIP Conf. Proc. 707 (2004), AxestoTranspose, vectorised; consecutive keys are face
    neighbours (tested)."""
    x = [c[:, a].astype(np.int64).copy() for a in range(3)]
    m = 1 << (bits - 1)
    q = m
    while q > 1:  # inverse undo excess work
        p = q - 1
        for i in range(3):
            bit = (x[i] & q) != 0
            if i == 0:
                x[0] = np.where(bit, x[0] ^ p, x[0])
            else:
                t = np.where(bit, 0, (x[0] ^ x[i]) & p)
                x[0] = np.where(bit, x[0] ^ p, x[0] ^ t)
                x[i] = x[i] ^ t
        q >>= 1
    for i in range(1, 3):  # Gray encode
        x[i] = x[i] ^ x[i - 1]
    t = np.zeros_like(x[0])
    q = m
    while q > 1:
        t = np.where((x[2] & q) != 0, t ^ (q - 1), t)
        q >>= 1
    for i in range(3):
        x[i] = x[i] ^ t
    key = np.zeros(len(c), dtype=np.int64)
    for b in range(bits - 1, -1, -1):
        for a in range(3):
            key = (key << 1) | ((x[a] >> b) & 1)
    return key


def sfc_key(c: np.ndarray, curve: str, bits: int | None = None) -> np.ndarray:
    """Key of block coordinates c; `bits` per axis fixed by the domain so that keys of two
    states of one scene compare (the curve's orientation depends on the number of levels)."""
    need = max(1, int(np.max(c)).bit_length()) if len(c) else 1
    bits = need if bits is None else bits
    if bits < need:
        raise ValueError(f"block coordinate {int(np.max(c))} needs {need} bits, {bits} given")
    if curve == "morton":
        return morton_key(c, bits)
    if curve == "hilbert":
        return hilbert_key(c, bits)
    raise ValueError(f"unknown curve '{curve}' (morton or hilbert)")


# ---------------------------------------------------------------------------------------------
# Geometry: particles per 4x4x4-node block
# ---------------------------------------------------------------------------------------------

BLOCK = 4  # nodes (cells) per block edge
PPC = 2  # points per cell per axis
SHIFT = 1  # added to the engine's block index so that coordinates are >= 0 (blocks at -1 exist)


@dataclass
class Geometry:
    coords: np.ndarray  # (n, 3) int64 block coordinates of occupied blocks (>= 0)
    weight: np.ndarray  # (n,) particles per block (float: deposited states are fractional)
    cell: float = 0.0  # m
    label: str = ""
    bits: int | None = None  # SFC levels per axis (the domain's, for the asteroid scene)

    @property
    def particles(self) -> float:
        return float(self.weight.sum())


def _merge(coords: list, weights: list) -> tuple[np.ndarray, np.ndarray]:
    c = np.concatenate(coords)
    w = np.concatenate(weights)
    lo = c.min(axis=0)
    span = int((c - lo).max()) + 1
    lin = ((c[:, 0] - lo[0]) * span + (c[:, 1] - lo[1])) * span + (c[:, 2] - lo[2])
    uniq, inv = np.unique(lin, return_inverse=True)
    coords = np.stack([uniq // (span * span), (uniq // span) % span, uniq % span], axis=1) + lo
    return coords, np.bincount(inv.ravel(), weights=w)


def sphere_block_counts(centre, radius, cell, lo, zmin=0.0):
    """Exact number of lattice points per owner block: PPC points per cell per axis at (i + 1/4)
    and (i + 3/4) cells from lo inside the sphere (the scene's fill), z > zmin only (the half
    model). The owner block holds the first node of a point's 3-node stencil
    (docs/architecture.md, Grid): a point at (c + 1/4) h starts at node c - 1, one at
    (c + 3/4) h at node c, so block B (engine index) owns the 8 points per axis at
    lo + 4 B h + (k + 3/2) h / 2, k = 0..7, and the points just above z = 0 belong to blocks at
    z index -1. Returned coordinates are the engine's block index + SHIFT (all >= 0). Blocks
    wholly inside count BLOCK^3 PPC^3 without testing."""
    bsize = BLOCK * cell
    centre = np.asarray(centre, float)
    lo = np.asarray(lo, float)
    first = 0.75 * cell  # offset of a block's first point from the block's first node
    bl = np.floor((centre - radius - lo - first) / bsize).astype(int)
    bh = np.floor((centre + radius - lo - first) / bsize).astype(int) + 1
    bl[2] = max(bl[2], int(np.floor((zmin - lo[2] - first) / bsize)))
    ax = [np.arange(bl[a], bh[a] + 1) for a in range(3)]
    g = np.stack(np.meshgrid(*ax, indexing="ij"), -1).reshape(-1, 3)
    plo = lo + g * bsize + first  # extent of the block's points
    phi = lo + g * bsize + first + (BLOCK * PPC - 1) * (cell / PPC)
    near = np.sqrt(np.sum((np.clip(centre, plo, phi) - centre) ** 2, axis=1))
    far = np.sqrt(np.sum(np.maximum(np.abs(plo - centre), np.abs(phi - centre)) ** 2, axis=1))
    zlow = plo[:, 2] <= zmin  # block straddles the symmetry plane
    full = (far < radius) & ~zlow
    edge = (near < radius) & ~full
    counts = [np.full(full.sum(), float(BLOCK**3 * PPC**3))]
    coords = [g[full]]
    eg = g[edge]
    off = first + np.arange(BLOCK * PPC) * (cell / PPC)  # point offsets inside a block
    for s in range(0, len(eg), 4096):
        e = eg[s:s + 4096]
        base = lo + e * bsize
        px = (base[:, 0, None] + off - centre[0]) ** 2
        py = (base[:, 1, None] + off - centre[1]) ** 2
        pzv = base[:, 2, None] + off
        pz = np.where(pzv > zmin, (pzv - centre[2]) ** 2, np.inf)
        r2 = px[:, :, None, None] + py[:, None, :, None] + pz[:, None, None, :]
        counts.append(np.count_nonzero(r2 < radius * radius, axis=(1, 2, 3)).astype(float))
        coords.append(e)
    c = np.concatenate(coords)
    w = np.concatenate(counts)
    keep = w > 0
    return c[keep] + SHIFT, w[keep]


def owner_block(x, cell, lo):
    """Owner block (engine index + SHIFT) of positions x (n, 3): the block of the first node of
    the 3-node stencil, round(x / h) - 1."""
    first = np.floor((x - lo) / cell + 0.5).astype(np.int64) - 1
    return np.floor_divide(first, BLOCK) + SHIFT


# The asteroid scene (scenes/asteroid-collision.toml; src/scene/impact.cpp places the projectile
# at target centre + (R + r) n - gap d, n = (-cos 45, sin 45, 0), d = +x).
DOMAIN_LO = np.array([-40e3, -40e3, 0.0])
DOMAIN_HI = np.array([40e3, 40e3, 40e3])
R_TARGET = 12.5e3
R_PROJ = 1.65e3
_A = math.radians(45.0)
PROJ_CENTRE = np.array([-(R_TARGET + R_PROJ) * math.cos(_A) - 500.0,
                        (R_TARGET + R_PROJ) * math.sin(_A), 0.0])
HALF_VOLUME = 2.0 / 3.0 * math.pi * (R_TARGET**3 + R_PROJ**3)


def cell_for_points(n_points: float) -> float:
    """Cell size giving about n_points in the half model, rounded so that the 80 km domain is a
    whole number of cells (the engine requires faces on grid planes)."""
    spacing = (HALF_VOLUME / n_points) ** (1.0 / 3.0)
    ncell = round((DOMAIN_HI[0] - DOMAIN_LO[0]) / (PPC * spacing))
    return (DOMAIN_HI[0] - DOMAIN_LO[0]) / ncell


def domain_bits(cell: float) -> int:
    return int(math.ceil((DOMAIN_HI - DOMAIN_LO).max() / (BLOCK * cell)) + SHIFT).bit_length()


def asteroid_initial(cell: float) -> Geometry:
    parts = [sphere_block_counts((0, 0, 0), R_TARGET, cell, DOMAIN_LO),
             sphere_block_counts(PROJ_CENTRE, R_PROJ, cell, DOMAIN_LO)]
    c, w = _merge([p[0] for p in parts], [p[1] for p in parts])
    return Geometry(c, w, cell, f"asteroid t=0, cell {cell:.1f} m", domain_bits(cell))


def deposit(positions, volumes, n_total, cell, label, max_sub=12) -> Geometry:
    """A later state at n_total points from a coarse snapshot: each coarse point stands for
    n_total / n_coarse fine points spread uniformly over a cube of its current volume (m / rho),
    sampled by sub^3 sub-points (sub ~ cube side / block side, 2..max_sub). Points beyond the
    symmetry plane are mirrored, points outside the domain dropped (outflow)."""
    bsize = BLOCK * cell
    side = np.cbrt(volumes)
    sub = np.clip(np.ceil(side / bsize).astype(int), 2, max_sub)
    per = n_total / len(positions)
    coords, weights = [], []
    for k in np.unique(sub):
        sel = sub == k
        u = (np.arange(k) + 0.5) / k - 0.5
        d = np.stack(np.meshgrid(u, u, u, indexing="ij"), -1).reshape(-1, 3)
        p = positions[sel, None, :] + side[sel, None, None] * d[None]
        p = p.reshape(-1, 3)
        p[:, 2] = np.abs(p[:, 2])
        inside = np.all((p >= DOMAIN_LO) & (p < DOMAIN_HI), axis=1)
        coords.append(owner_block(p[inside], cell, DOMAIN_LO))
        weights.append(np.full(inside.sum(), per / k**3))
    c, w = _merge(coords, weights)
    return Geometry(c, w, cell, label, domain_bits(cell))


def uniform_cube(n_blocks: int, per_block: float = 512.0) -> Geometry:
    g = np.stack(np.meshgrid(*(np.arange(n_blocks),) * 3, indexing="ij"), -1).reshape(-1, 3)
    return Geometry(g.astype(np.int64), np.full(len(g), per_block), 1.0, f"cube {n_blocks}^3")


# ---------------------------------------------------------------------------------------------
# Decomposition and halo
# ---------------------------------------------------------------------------------------------

OFFSETS = np.array([[i, j, k] for i in (0, 1) for j in (0, 1) for k in (0, 1)], dtype=np.int64)
# Owner of a block that holds no particle (reached only): the rank of the occupied block that
# reaches most of its nodes: face neighbours first, then edges, then the corner.
REACH_ORDER = [o for o in sorted(range(8), key=lambda i: (OFFSETS[i].sum(), i)) if o != 0]


@dataclass
class Topology:
    """Per-geometry index structure, independent of the rank count."""
    geom: Geometry
    alloc: np.ndarray  # (m, 3) allocated blocks (occupied and reached)
    reach: np.ndarray  # (m, 8) index of occupied block alloc - OFFSETS[o], or -1
    keys: dict = field(default_factory=dict)


def topology(geom: Geometry) -> Topology:
    c = geom.coords + 1  # room for the -1 of a reached block's reacher lookup
    span = int(c.max()) + 3
    lin = (c[:, 0] * span + c[:, 1]) * span + c[:, 2]
    order = np.argsort(lin)
    slin = lin[order]
    olin = (OFFSETS[:, 0] * span + OFFSETS[:, 1]) * span + OFFSETS[:, 2]
    alin = np.unique((lin[:, None] + olin[None, :]).ravel())
    alloc = np.stack([alin // (span * span), (alin // span) % span, alin % span], axis=1)
    reach = np.full((len(alloc), 8), -1, dtype=np.int64)
    for i, o in enumerate(OFFSETS):
        q = alin - ((o[0] * span + o[1]) * span + o[2])
        pos = np.clip(np.searchsorted(slin, q), 0, len(slin) - 1)
        hit = slin[pos] == q
        reach[hit, i] = order[pos[hit]]
    return Topology(geom, alloc - 1, reach)


def cut(keys: np.ndarray, weight: np.ndarray, ranks: int, rule: str = "midpoint") -> np.ndarray:
    """Contiguous chunks of equal weight along the curve. 'midpoint': a block goes to the chunk
    holding its weight's midpoint; 'prefix': rank r starts at the first block with at least
    ceil(W r / P) of the weight before it (the mpi helper's Decomposition::build). Either way a
    rank is off the mean by less than one block. Returns the first key of each rank."""
    order = np.argsort(keys, kind="stable")
    if rule == "prefix":
        before = np.cumsum(weight[order]) - weight[order]
        target = np.ceil(weight.sum() * np.arange(ranks) / ranks)
        first = np.searchsorted(before, target, side="left")
        first[0] = 0
    else:
        mid = np.cumsum(weight[order]) - 0.5 * weight[order]
        rank = np.minimum((mid * ranks / weight.sum()).astype(np.int64), ranks - 1)
        first = np.searchsorted(rank, np.arange(ranks))  # empty ranks: the next rank's start
    starts = np.where(first < len(order), keys[order][np.minimum(first, len(order) - 1)],
                      np.iinfo(np.int64).max)
    starts[0] = np.iinfo(np.int64).min
    return starts


def owners_from_cuts(keys: np.ndarray, starts: np.ndarray) -> np.ndarray:
    return np.searchsorted(starts, keys, side="right") - 1


@dataclass
class Halo:
    ranks: int
    particles: np.ndarray  # per rank
    pair_src: np.ndarray  # (k,) rank sending partial sums (reaches the nodes)
    pair_dst: np.ndarray  # (k,) owner of the nodes
    pair_nodes: np.ndarray  # (k,) nodes
    alloc_extra: np.ndarray  # per rank: nodes reached in other ranks' blocks


def halo(top: Topology, owner_occ: np.ndarray, ranks: int, owner_alloc=None) -> Halo:
    """Halo of a decomposition: owner_occ per occupied block; owner_alloc per allocated block
    (top.alloc), or None for the 'reacher' rule (a reached-only block belongs to the occupied
    block reaching most of its nodes, REACH_ORDER)."""
    geom = top.geom
    reach = top.reach
    occ_of = np.where(reach >= 0, owner_occ[np.maximum(reach, 0)], -1)  # (m, 8) rank of B - o
    if owner_alloc is None:
        own = occ_of[:, 0].copy()
        for o in REACH_ORDER:
            own = np.where(own < 0, occ_of[:, o], own)
    else:
        own = np.asarray(owner_alloc)
        occupied = occ_of[:, 0] >= 0
        assert np.array_equal(own[occupied], occ_of[occupied, 0])
    pairs = []
    for c in range(8):
        cols = [o for o in range(8) if np.all(OFFSETS[o] <= OFFSETS[c])]
        r = np.sort(occ_of[:, cols], axis=1)
        first = np.ones_like(r, dtype=bool)
        first[:, 1:] = r[:, 1:] != r[:, :-1]
        take = first & (r >= 0) & (r != own[:, None])
        rows = np.nonzero(take)[0]
        pairs.append(r[take] * ranks + own[rows])
    pairs = np.concatenate(pairs)
    uniq, cnt = np.unique(pairs, return_counts=True)
    src, dst = uniq // ranks, uniq % ranks
    nodes = cnt * 8  # 8 nodes per class
    extra = np.bincount(src, weights=nodes, minlength=ranks)
    parts = np.bincount(owner_occ, weights=geom.weight, minlength=ranks)
    return Halo(ranks, parts, src, dst, nodes.astype(np.int64), extra)


def decompose(top: Topology, ranks: int, curve: str, starts=None, rule: str = "midpoint"):
    """Owner of each occupied block for `ranks` ranks; with `starts` (cut keys of an earlier
    state) the ranks keep their key intervals (no rebalancing)."""
    if curve not in top.keys:
        bits = top.geom.bits
        if bits is not None:  # reached blocks lie one beyond the occupied ones
            bits = max(bits, int(top.alloc.max()).bit_length())
        top.keys[curve] = (sfc_key(top.geom.coords, curve, bits),
                           sfc_key(top.alloc, curve, bits))
    keys = top.keys[curve][0]
    if starts is None:
        starts = cut(keys, top.geom.weight, ranks, rule)
    return owners_from_cuts(keys, starts), starts


def alloc_owner_by_interval(top: Topology, curve: str, starts) -> np.ndarray:
    """The 'interval' rule (the mpi helper's Decomposition::rank_of): every block key, occupied
    or not, belongs to the rank whose curve interval holds it."""
    return owners_from_cuts(top.keys[curve][1], starts)


# ---------------------------------------------------------------------------------------------
# Time per step
# ---------------------------------------------------------------------------------------------


@dataclass
class StepCost:
    ranks: int
    particles: float
    per_rank_mean: float
    imbalance: float  # max / mean particles
    halo_bytes: float  # per step, all ranks, all phases (sent)
    halo_bytes_max: float  # per step, the rank that sends + receives most
    messages_max: int  # per step, point-to-point messages sent by the busiest rank
    neighbours_mean: float
    neighbours_max: int
    t_compute: float
    t_comm: float
    t_step: float
    t_serial: float
    parts: dict


def step_cost(h: Halo, prm: Params) -> StepCost:
    p = h.ranks
    node = np.arange(p) // prm.ranks_per_node
    intra = node[h.pair_src] == node[h.pair_dst]
    alpha = np.where(intra, prm.alpha_shm, prm.alpha_net)
    beta = np.where(intra, prm.beta_shm, prm.beta_net)
    t_comm = 0.0
    bytes_total = 0.0
    per_rank_bytes = np.zeros(p)
    parts = {}
    # Each phase: partial sums src -> dst (scatter) or final values dst -> src (return). A rank
    # handles its outgoing and incoming messages one after the other (alpha + m / beta each);
    # a node's inter-node bytes share one NIC. Phase time = slowest rank (a synchronisation).
    for i, nd in enumerate(prm.phase_doubles):
        m = h.pair_nodes * nd * 8.0
        tmsg = alpha + m / beta
        a, b = (h.pair_src, h.pair_dst) if i % 2 == 0 else (h.pair_dst, h.pair_src)
        t_out = np.bincount(a, weights=tmsg, minlength=p)
        t_in = np.bincount(b, weights=tmsg, minlength=p)
        nic = np.bincount(node[a], weights=np.where(intra, 0.0, m),
                          minlength=node[-1] + 1) / prm.beta_net
        t_phase = np.max(np.maximum(np.maximum(t_out, t_in), nic[node])) if len(m) else 0.0
        parts[f"phase{i}"] = t_phase
        t_comm += t_phase
        bytes_total += m.sum()
        per_rank_bytes += np.bincount(a, weights=m, minlength=p) + np.bincount(b, weights=m,
                                                                              minlength=p)
    # Migration: particles in the cell layer next to a rank boundary (half the 2 node layers a
    # rank sends, 8 points per cell) times the fraction of a cell crossed per step; one message
    # per neighbour pair in each direction.
    mig_m = h.pair_nodes / 2.0 * 8.0 * prm.migrate_fraction * prm.migrant_bytes
    tmig = alpha + mig_m / beta
    t_mig = 0.0
    if len(mig_m):
        t_mig = np.max(np.maximum(np.bincount(h.pair_src, weights=tmig, minlength=p),
                                  np.bincount(h.pair_dst, weights=tmig, minlength=p)))
    parts["migration"] = t_mig
    t_comm += t_mig
    bytes_total += mig_m.sum()
    # Allreduces: a tree of log2(P) latency terms (inter-node alpha once P spans nodes).
    if p > 1:
        a_red = prm.alpha_net if p > prm.ranks_per_node else prm.alpha_shm
        t_red = prm.allreduces_per_step * math.ceil(math.log2(p)) * a_red
    else:
        t_red = 0.0
    parts["allreduce"] = t_red
    t_comm += t_red
    # Compute: particles x t_p, plus grid work on the nodes reached in others' blocks and the
    # packing of every byte sent and received.
    tp = prm.t_particle_ns * 1e-9
    t_rank = (h.particles * tp + h.alloc_extra * prm.t_node_ns * 1e-9
              + per_rank_bytes / prm.copy_bandwidth)
    t_compute = float(np.max(t_rank))
    parts["compute_mean"] = float(np.mean(h.particles * tp))
    n_out = np.bincount(h.pair_src, minlength=p) if len(h.pair_src) else np.zeros(p, int)
    n_in = np.bincount(h.pair_dst, minlength=p) if len(h.pair_src) else np.zeros(p, int)
    nb = np.zeros(p, dtype=np.int64)
    if len(h.pair_src):
        s = np.unique(np.concatenate([h.pair_src * p + h.pair_dst, h.pair_dst * p + h.pair_src]))
        nb = np.bincount(s // p, minlength=p)
    # messages sent per step: scatter phases to n_out ranks, returns to n_in, migration to both
    msgs = 2 * n_out + 2 * n_in + n_out + n_in
    total = h.particles.sum()
    return StepCost(
        ranks=p, particles=float(total), per_rank_mean=float(total / p),
        imbalance=float(h.particles.max() / (total / p)), halo_bytes=float(bytes_total),
        halo_bytes_max=float(per_rank_bytes.max()), messages_max=int(msgs.max()),
        neighbours_mean=float(nb.mean()), neighbours_max=int(nb.max()),
        t_compute=t_compute, t_comm=float(t_comm), t_step=t_compute + float(t_comm),
        t_serial=float(total * tp), parts=parts)


def analyse(top: Topology, ranks: int, curve: str, prm: Params, starts=None,
            empty: str = "interval") -> StepCost:
    """empty: who owns a block that holds no particle but is reached ('interval': the rank
    whose key interval holds it, the mpi helper's rule; 'reacher': see halo())."""
    own, starts = decompose(top, ranks, curve, starts)
    alloc = alloc_owner_by_interval(top, curve, starts) if empty == "interval" else None
    return step_cost(halo(top, own, ranks, alloc), prm)


# ---------------------------------------------------------------------------------------------
# Validation cases with known answers (python/tests/test_scaling_model.py runs them)
# ---------------------------------------------------------------------------------------------


def cube_halo_expected(n_blocks: int, parts: int) -> int:
    """Halo node incidences of a cube of n^3 full blocks cut into 2 halves or 8 octants: per
    axis the footprint is 4n + 2 nodes and a cut plane adds the 2 node layers both sides reach,
    so the sum over nodes of (reaching ranks - 1) is (4n + 2 + 2 k_a) products minus (4n + 2)^3,
    k_a = 1 for a cut axis."""
    f = BLOCK * n_blocks + 2
    cuts = {2: (1, 0, 0), 8: (1, 1, 1)}[parts]
    prod = 1
    for k in cuts:
        prod *= f + 2 * k
    return prod - f**3


def brute_force_halo(geom: Geometry, owner_occ: np.ndarray, ranks: int,
                     empty_owner=None) -> dict:
    """Node-by-node reference: every occupied block reaches its 6^3 nodes; a node belongs to
    its block's owner (for a reached-only block, empty_owner(block tuple) or else the
    REACH_ORDER rule); returns {(src, dst): nodes}. Small geometries only."""
    reached: dict = {}
    for b, r in zip(geom.coords, owner_occ):
        base = b * BLOCK
        for i in range(BLOCK + 2):
            for j in range(BLOCK + 2):
                for k in range(BLOCK + 2):
                    reached.setdefault((base[0] + i, base[1] + j, base[2] + k), set()).add(int(r))
    occ = {tuple(b): int(r) for b, r in zip(geom.coords, owner_occ)}

    def block_owner(bc):
        if bc in occ:
            return occ[bc]
        if empty_owner is not None:
            return empty_owner(bc)
        for o in REACH_ORDER:
            nb = tuple(int(x) for x in np.array(bc) - OFFSETS[o])
            if nb in occ:
                return occ[nb]
        raise AssertionError("unreached block")

    out: dict = {}
    for n, rs in reached.items():
        q = block_owner(tuple(int(x) // BLOCK for x in n))
        for r in rs - {q}:
            out[(r, q)] = out.get((r, q), 0) + 1
    return out


# ---------------------------------------------------------------------------------------------
# Driver
# ---------------------------------------------------------------------------------------------

RANKS = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]


def fmt_bytes(b: float) -> str:
    for unit, s in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if b >= s:
            return f"{b / s:.3g} {unit}"
    return f"{b:.0f} B"


def table(rows: list[StepCost], base_step=None) -> str:
    """Markdown table; efficiency = T_1 / (P T_P) for strong scaling (base_step None) or
    T_1(n) / T_P(P n) for weak scaling (base_step = the 1-rank step time)."""
    out = ["| P | particles/rank | compute (ms) | halo bytes/step (all ranks) | busiest rank: bytes, "
           "messages | neighbours mean/max | comm (ms) | imbalance | efficiency |",
           "|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        eff = (r.t_serial / (r.ranks * r.t_step)) if base_step is None else base_step / r.t_step
        out.append(f"| {r.ranks} | {r.per_rank_mean:,.0f} | {r.t_compute * 1e3:.3g} | "
                   f"{fmt_bytes(r.halo_bytes)} | {fmt_bytes(r.halo_bytes_max)}, {r.messages_max} | "
                   f"{r.neighbours_mean:.1f} / {r.neighbours_max} | {r.t_comm * 1e3:.3g} | "
                   f"{r.imbalance:.3f} | {eff * 100:.1f}% |")
    return "\n".join(out)


def efficiency(rows, weak=False):
    if weak:
        return [rows[0].t_step / r.t_step for r in rows]
    return [r.t_serial / (r.ranks * r.t_step) for r in rows]


def load_snapshot(path):
    import h5py
    with h5py.File(path, "r") as f:
        x = f["particles/position"][:]
        vol = f["particles/mass"][:] / f["particles/rho"][:]
        t = float(f.attrs["time"])
    return x, vol, t


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--points", type=float, default=1e8, help="strong-scaling size (half model)")
    ap.add_argument("--weak", type=float, nargs="*", default=[1e5, 1e6],
                    help="particles per rank for weak scaling")
    ap.add_argument("--max-ranks", type=int, default=1024)
    ap.add_argument("--debris", type=Path, help="run folder of a coarse asteroid run (snapshots)")
    ap.add_argument("--debris-times", type=float, nargs="*", default=[5.0, 15.0, 50.0, 100.0])
    ap.add_argument("--drift", type=Path, help="run folder with closely spaced snapshots: "
                    "imbalance when each snapshot's cuts serve until the next")
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures" / "scaling")
    ap.add_argument("--tables", type=Path, help="write the markdown tables here")
    ap.add_argument("--t-particle-ns", type=float, default=Params.t_particle_ns)
    ap.add_argument("--quick", action="store_true", help="skip weak scaling at 1e6 per rank")
    args = ap.parse_args(argv)
    prm = Params(t_particle_ns=args.t_particle_ns)
    ranks = [r for r in RANKS if r <= args.max_ranks]
    md = []
    csv_rows = []
    curves = ("hilbert", "morton")

    # Scene files: point counts of the generator against the engine's (checked in the doc).
    md.append("## Scene sizes (geometry check)\n")
    md.append("| cell (m) | points (model) | blocks |\n|---:|---:|---:|")
    scene_tops = {}
    for cell in (1000.0, 500.0):
        g = asteroid_initial(cell)
        scene_tops[cell] = topology(g)
        md.append(f"| {cell:.0f} | {g.particles:,.0f} | {len(g.weight):,} |")
    md.append(small_runs_table(scene_tops, prm))

    # Strong scaling at args.points.
    cell = cell_for_points(args.points)
    g = asteroid_initial(cell)
    top = topology(g)
    print(f"strong: cell {cell:.2f} m, {g.particles:.4g} points, {len(g.weight)} blocks,"
          f" {len(top.alloc)} allocated", file=sys.stderr)
    strong = {}
    for curve in curves:
        strong[curve] = [analyse(top, p, curve, prm) for p in ranks]
        for r in strong[curve]:
            csv_rows.append(("strong", f"{args.points:g}", curve, r))
    for curve in curves:
        md.append(f"\n## Strong scaling, {g.particles:,.0f} points (cell {cell:.2f} m), {curve}\n")
        md.append(table(strong[curve]))
    scene_strong = {}
    for cell_s, t in scene_tops.items():
        scene_strong[cell_s] = [analyse(t, p, "hilbert", prm) for p in ranks]
        md.append(f"\n## Strong scaling, scene at {cell_s:.0f} m ({t.geom.particles:,.0f} points),"
                  " hilbert\n")
        md.append(table(scene_strong[cell_s]))
        for r in scene_strong[cell_s]:
            csv_rows.append(("strong", f"{t.geom.particles:.0f}", "hilbert", r))

    # Weak scaling.
    weak = {}
    for n in args.weak:
        if args.quick and n > 2e5:
            continue
        for curve in curves:
            rows = []
            for p in ranks:
                gw = asteroid_initial(cell_for_points(n * p))
                rows.append(analyse(topology(gw), p, curve, prm))
                print(f"weak {n:g} {curve} P={p}: {gw.particles:.4g} points", file=sys.stderr)
            weak[(n, curve)] = rows
            for r in rows:
                csv_rows.append(("weak", f"{n:g}", curve, r))
            md.append(f"\n## Weak scaling, {n:,.0f} points per rank, {curve}\n")
            md.append(table(rows, base_step=rows[0].t_step))

    # Beyond 1024 ranks (Hilbert), to find where the 1e8-point run drops below 80 %.
    beyond = [analyse(top, p, "hilbert", prm) for p in (2048, 4096, 8192, 16384)]
    md.append(f"\n## Strong scaling beyond 1024 ranks, {g.particles:,.0f} points, hilbert\n")
    md.append(table(beyond))
    # Where the communication time goes (Hilbert, 1e8): latency only (beta infinite),
    # bandwidth only (alpha 0), per term.
    md.append(f"\n## Communication per step split, {g.particles:,.0f} points, hilbert (ms)\n")
    md.append("| P | total comm | latency only | bandwidth only | P2G scatter+return | "
              "remap scatter+return | migration | allreduces | packing (in compute) |")
    md.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    lat = Params(**{**prm.__dict__, "beta_net": 1e30, "beta_shm": 1e30, "copy_bandwidth": 1e30})
    bw = Params(**{**prm.__dict__, "alpha_net": 0.0, "alpha_shm": 0.0})
    for p in (64, 256, 1024, 4096, 16384):
        own, st = decompose(top, p, "hilbert")
        hh = halo(top, own, p, alloc_owner_by_interval(top, "hilbert", st))
        a, b_, c_ = step_cost(hh, prm), step_cost(hh, lat), step_cost(hh, bw)
        pk = (a.t_compute - np.max(hh.particles * prm.t_particle_ns * 1e-9))
        md.append(f"| {p} | {a.t_comm * 1e3:.3g} | {b_.t_comm * 1e3:.3g} | {c_.t_comm * 1e3:.3g} | "
                  f"{(a.parts['phase0'] + a.parts['phase1']) * 1e3:.3g} | "
                  f"{(a.parts['phase2'] + a.parts['phase3']) * 1e3:.3g} | "
                  f"{a.parts['migration'] * 1e3:.3g} | {a.parts['allreduce'] * 1e3:.3g} | "
                  f"{pk * 1e3:.3g} |")

    # Who owns reached-only blocks: the key interval (the mpi helper's rule) or a reaching rank.
    md.append(f"\n## Reached-only blocks: interval rule against reacher rule, {g.particles:,.0f} "
              "points\n")
    md.append("| curve | P | halo bytes/step interval / reacher | neighbours mean (max) interval / "
              "reacher | efficiency interval / reacher |")
    md.append("|---|---:|---:|---:|---:|")
    for curve in curves:
        for p in (64, 256, 1024):
            a = analyse(top, p, curve, prm, empty="interval")
            b_ = analyse(top, p, curve, prm, empty="reacher")
            md.append(f"| {curve} | {p} | {fmt_bytes(a.halo_bytes)} / {fmt_bytes(b_.halo_bytes)} | "
                      f"{a.neighbours_mean:.1f} ({a.neighbours_max}) / {b_.neighbours_mean:.1f} "
                      f"({b_.neighbours_max}) | {a.t_serial / (p * a.t_step) * 100:.1f}% / "
                      f"{b_.t_serial / (p * b_.t_step) * 100:.1f}% |")

    # Hybrid: one rank per node of 64 cores, TBB threads inside (perfect threading assumed):
    # compute per particle-step / 64, every message inter-node.
    # Packing by the node's threads at ~100 GB/s of copy (a third of a two-socket node's STREAM).
    hyb = Params(**{**prm.__dict__, "t_particle_ns": prm.t_particle_ns / 64.0,
                    "ranks_per_node": 1, "copy_bandwidth": 100e9 / 2})
    hyb_rows = [analyse(top, p, "hilbert", hyb) for p in ranks]
    md.append(f"\n## Strong scaling, {g.particles:,.0f} points, hilbert, hybrid: one rank per "
              "64-core node (P = nodes), compute 525/64 ns per particle-step\n")
    md.append(table(hyb_rows))

    # Faster compute (issue 12's target): the same decompositions, compute 200 ns.
    fast = Params(t_particle_ns=200.0)
    fast_rows = [analyse(top, p, "hilbert", fast) for p in ranks]
    md.append(f"\n## Strong scaling, {g.particles:,.0f} points, hilbert, compute 200 ns "
              "per particle-step (issue 12's target)\n")
    md.append(table(fast_rows))

    # Debris: a coarse run's snapshots deposited at args.points.
    debris = []
    if args.debris:
        snaps = sorted((args.debris / "snapshots").glob("snapshot_*.h5"))
        x0, v0, _ = load_snapshot(snaps[0])
        n0 = len(x0)
        g0 = deposit(x0, v0, args.points, cell, "deposited t=0")
        top0 = topology(g0)
        md.append("\n## Debris cloud (coarse run deposited at the strong-scaling size), hilbert\n")
        md.append(f"t = 0 deposited: {g0.particles:,.0f} points in {len(g0.weight):,} blocks "
                  f"(exact lattice: {g.particles:,.0f} in {len(g.weight):,}).\n")
        md.append("| t (s) | P | occupied blocks | imbalance, t=0 cuts | efficiency, t=0 cuts | "
                  "imbalance, rebalanced | halo bytes/step rebalanced | efficiency, rebalanced | "
                  "particles a recut moves |")
        md.append("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        wanted = [0.0] + list(args.debris_times)
        seen = set()
        for tw in wanted:
            best = None
            for s in snaps:
                with __import__("h5py").File(s, "r") as f:
                    ts = float(f.attrs["time"])
                if best is None or abs(ts - tw) < abs(best[1] - tw):
                    best = (s, ts)
            if best[0] in seen:
                continue
            seen.add(best[0])
            x, vol, ts = load_snapshot(best[0])
            gt = deposit(x, vol, args.points * len(x) / n0, cell, f"t={ts:g}")
            tt = topology(gt)
            for p in (64, 256, 1024):
                if p > args.max_ranks:
                    continue
                _, starts0 = decompose(top0, p, "hilbert")
                old = analyse(tt, p, "hilbert", prm, starts=starts0)
                new = analyse(tt, p, "hilbert", prm)
                e_old = old.t_serial / (p * old.t_step)
                e_new = new.t_serial / (p * new.t_step)
                o_old, _ = decompose(tt, p, "hilbert", starts0)
                o_new, _ = decompose(tt, p, "hilbert")
                moved = gt.weight[o_old != o_new].sum() / gt.particles
                debris.append((ts, p, old, new, e_old, e_new))
                md.append(f"| {ts:g} | {p} | {len(gt.weight):,} | {old.imbalance:.2f} | "
                          f"{e_old * 100:.1f}% | {new.imbalance:.3f} | {fmt_bytes(new.halo_bytes)} | "
                          f"{e_new * 100:.1f}% | {moved * 100:.1f}% |")
            print(f"debris t={ts:g}: {gt.particles:.4g} points, {len(gt.weight)} blocks",
                  file=sys.stderr)

    if args.drift:
        md.append(drift_table(args.drift, args.points, cell, prm, [p for p in (64, 256, 1024)
                                                                     if p <= args.max_ranks]))

    text = "\n".join(md) + "\n"
    if args.tables:
        args.tables.write_text(text)
    else:
        print(text)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with open(args.out.with_suffix(".csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["kind", "size", "curve", "ranks", "particles", "per_rank", "imbalance",
                    "halo_bytes", "halo_bytes_max", "messages_max", "neighbours_mean",
                    "neighbours_max", "t_compute_s", "t_comm_s", "t_step_s", "efficiency"])
        for kind, size, curve, r in csv_rows:
            if kind == "strong":
                eff = r.t_serial / (r.ranks * r.t_step)
            else:
                eff = weak[(float(size), curve)][0].t_step / r.t_step
            w.writerow([kind, size, curve, r.ranks, f"{r.particles:.0f}", f"{r.per_rank_mean:.1f}",
                        f"{r.imbalance:.4f}", f"{r.halo_bytes:.0f}", f"{r.halo_bytes_max:.0f}",
                        r.messages_max, f"{r.neighbours_mean:.2f}", r.neighbours_max,
                        f"{r.t_compute:.6g}", f"{r.t_comm:.6g}", f"{r.t_step:.6g}", f"{eff:.4f}"])
    plot(args.out, ranks, g, strong, scene_strong, weak, fast_rows, hyb_rows, debris)


def small_runs_table(tops: dict, prm: Params) -> str:
    """What `mpirun -np 1..4 shatter run scenes/asteroid-collision.toml` should exchange, with
    the mpi helper's choices (Morton, interval rule), for comparison with docs/mpi.md."""
    out = ["\n## The scene on 1-4 ranks (Morton, prefix cut, interval rule: the mpi helper's "
           "choices)\n",
           "| cell (m) | P | halo nodes (all pairs) | P2G scatter bytes/step | all halo phases "
           "bytes/step | messages/step (all ranks, halo phases) | particles per rank (min-max) |",
           "|---:|---:|---:|---:|---:|---:|---:|"]
    for cell, top in tops.items():
        for p in (1, 2, 3, 4):
            own, starts = decompose(top, p, "morton", rule="prefix")
            h = halo(top, own, p, alloc_owner_by_interval(top, "morton", starts))
            nodes = int(h.pair_nodes.sum())
            d = prm.phase_doubles
            out.append(f"| {cell:.0f} | {p} | {nodes:,} | {nodes * d[0] * 8:,} | "
                       f"{nodes * sum(d) * 8:,} | {4 * len(h.pair_src)} | "
                       f"{h.particles.min():,.0f}-{h.particles.max():,.0f} |")
    return "\n".join(out)


def drift_table(run: Path, points: float, cell: float, prm: Params, ps) -> str:
    """Cuts made at snapshot i serve until snapshot i + 1: imbalance and efficiency just before
    the next recut, and the share of particles that recut moves."""
    snaps = sorted((run / "snapshots").glob("snapshot_*.h5"))
    n0 = None
    out = [f"\n## Drift between recuts ({run.name}: snapshots every "
           "Delta t, cuts of one snapshot used at the next), hilbert\n",
           "| t (s) | Delta t (s) | " + " | ".join(f"P={p}: imbalance, efficiency, moved by recut"
                                                  for p in ps) + " |",
           "|---:|---:|" + "---:|" * len(ps)]
    prev = None
    for s in snaps:
        x, vol, ts = load_snapshot(s)
        n0 = n0 or len(x)
        gt = deposit(x, vol, points * len(x) / n0, cell, f"t={ts:g}")
        tt = topology(gt)
        if prev is not None:
            cells = []
            for p in ps:
                _, starts = decompose(prev[1], p, "hilbert")
                old = analyse(tt, p, "hilbert", prm, starts=starts)
                o_old, _ = decompose(tt, p, "hilbert", starts)
                o_new, _ = decompose(tt, p, "hilbert")
                moved = gt.weight[o_old != o_new].sum() / gt.particles
                cells.append(f"{old.imbalance:.2f}, {old.t_serial / (p * old.t_step) * 100:.0f}%, "
                             f"{moved * 100:.1f}%")
            out.append(f"| {ts:g} | {ts - prev[0]:g} | " + " | ".join(cells) + " |")
            print(f"drift t={ts:g}", file=sys.stderr)
        prev = (ts, tt)
    return "\n".join(out)


def plot(out, ranks, g, strong, scene_strong, weak, fast_rows, hyb_rows, debris):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    a = ax[0]
    a.semilogx(ranks, np.array(efficiency(strong["hilbert"])) * 100, "o-",
               label=f"{g.particles:.2g} points, Hilbert")
    a.semilogx(ranks, np.array(efficiency(strong["morton"])) * 100, "s--",
               label=f"{g.particles:.2g} points, Morton")
    a.semilogx(ranks, np.array(efficiency(fast_rows)) * 100, "^-",
               label=f"{g.particles:.2g}, compute 200 ns (issue 12 target)")
    a.semilogx(ranks, np.array(efficiency(hyb_rows)) * 100, "v-",
               label=f"{g.particles:.2g}, hybrid: P = 64-core nodes")
    for cell, rows in scene_strong.items():
        a.semilogx(ranks, np.array(efficiency(rows)) * 100, "x:",
                   label=f"scene at {cell:.0f} m ({rows[0].particles:,.0f} points)")
    a.axhline(80, color="grey", lw=0.8)
    a.set_xlabel("ranks P")
    a.set_ylabel("parallel efficiency (%)")
    a.set_title("strong scaling (asteroid collision, half model)")
    a.set_ylim(0, 105)
    a.legend(fontsize=7, loc="lower left")
    a = ax[1]
    for (n, curve), rows in weak.items():
        a.semilogx([r.ranks for r in rows], np.array(efficiency(rows, weak=True)) * 100,
                   "o-" if curve == "hilbert" else "s--", label=f"{n:.0e} points/rank, {curve}")
    a.axhline(80, color="grey", lw=0.8)
    a.set_xlabel("ranks P")
    a.set_title("weak scaling")
    a.set_ylim(0, 105)
    a.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=110)
    if debris:
        fig, a = plt.subplots(figsize=(6, 4))
        for i, p in enumerate(sorted({d[1] for d in debris})):
            ds = [d for d in debris if d[1] == p]
            a.plot([d[0] for d in ds], [d[4] * 100 for d in ds], "o--", color=f"C{i}",
                   label=f"P={p}, t=0 cuts")
            a.plot([d[0] for d in ds], [d[5] * 100 for d in ds], "s-", color=f"C{i}",
                   label=f"P={p}, rebalanced")
        a.axhline(80, color="grey", lw=0.8)
        a.set_xlabel("simulated time (s)")
        a.set_ylabel("parallel efficiency (%)")
        a.set_title("debris cloud: decomposition kept from t = 0 vs rebalanced")
        a.set_ylim(0, 105)
        a.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out.parent / (out.name + "_debris.png"), dpi=110)


if __name__ == "__main__":
    main()
