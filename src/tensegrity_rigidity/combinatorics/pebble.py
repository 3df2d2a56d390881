"""Compiled kernel of the fixed-torus pebble game (integer arithmetic only).

State of a game on ``N`` nodes and ``m`` bond sites:

* ``out : (N, 2) int64``: the two pebble slots of each node; a slot holds ``-1`` (a free pebble)
  or the index of an accepted bond oriented *out of* that node;
* ``eu, ev : (m,) int64`` and ``gx, gy : (m,) int64``: the two ends of each bond and its gain
  (the image shift of ``ev`` seen from ``eu``; seen from ``ev`` the gain is ``-(gx, gy)``).

A *lifted* node is a pair (node, potential): the image of the node shifted by the potential, an
integer vector. The balancedness of a bond set is read off the potentials met when walking its
bonds in the lift (docs/guide/rigid-clusters.md states the rules and why they are right).

Bond status codes (:data:`INDEPENDENT` ...) are what :func:`play` returns per site.

The compiled functions do not check their indices (an order naming a site past ``m`` reads and
writes outside the arrays: a segmentation fault, or a wrong answer): call them through
:mod:`~tensegrity_rigidity.combinatorics.clusters`, whose every entry checks the network and
the order first.
"""

from __future__ import annotations

import numba as nb
import numpy as np

#: status of a site not (yet) inserted: empty, or after the pass stopped
UNTESTED = 0
#: accepted into the independent set of the fixed-torus matroid
INDEPENDENT = 1
#: dependent, and its fundamental circuit is balanced (no cycle of it wraps): zero virial
BALANCED = 2
#: dependent, and its fundamental circuit is unbalanced: it resists a generic strain
UNBALANCED = 3

#: node indices must stay below this (the kernel's arrays are int64 throughout)
MAX_NODES = 1 << 30
#: image shifts must stay below this, so that potentials (sums of at most N shifts) fit too
MAX_SHIFT = 1 << 30

#: pebbles per node (its two coordinates); ``out`` has one slot per pebble
PEBBLES = 2
#: pebbles gathered on a new bond's two ends that make it independent whatever its gain
ALL_FREE = 2 * PEBBLES
#: pebbles gathered when the smallest node set holding both ends has ``2 |U| - 3`` bonds
ONE_SHORT = ALL_FREE - 1
#: columns of a lifted path row: bond, tail node and potential (x, y), head node and potential
PATH_COLUMNS = 7

#: rows of the kernel's (ROWS, N) int64 work array
SEEN, PRED, LIST, PX, PY, SEEN2, PRED2, LIST2, ONPATH, MARK, STACK = range(11)
ROWS = 11
#: rows of the cluster labelling's (LABEL_ROWS, N) int64 work array: per node the stamp of
#: the search visiting it and its potential there, the cluster holding it and its potential in
#: it, and the wrapping cluster holding it (-1: none)
VISITED, TPX, TPY, TLIST, MEMBER, MPX, MPY, WRAP_OF = range(8)
LABEL_ROWS = 8


@nb.njit(cache=True)
def _free(out, v):
    return int(out[v, 0] < 0) + int(out[v, 1] < 0)


@nb.njit(cache=True)
def _step(b, v, eu, ev, gx, gy):
    """Other end of bond b seen from v, and the gain from v to it."""
    if eu[b] == v:
        return ev[b], gx[b], gy[b]
    return eu[b], -gx[b], -gy[b]


@nb.njit(cache=True)
def _move(out, b, src, dst):
    """Re-orient bond b from node src to node dst (dst must have a free slot)."""
    if out[src, 0] == b:
        out[src, 0] = -1
    else:
        out[src, 1] = -1
    if out[dst, 0] < 0:
        out[dst, 0] = b
    else:
        out[dst, 1] = b


@nb.njit(cache=True)
def _search(root, a, c, ends_only, out, eu, ev, seen, stamp, pred, queue, breadth):
    """Search along the orientation from ``root`` for a node holding a free pebble.

    The node sought is any node but ``root`` and ``a`` (``ends_only`` False), or one of ``a``,
    ``c`` (``ends_only`` True). Depth first, or breadth first with ``breadth`` (the nearest
    pebble). Records in ``pred`` the bond that reached each node; returns the node found, -1 if
    there is none.
    """
    stamp[0] += 1
    st = stamp[0]
    seen[root] = st
    head = 0
    top = 0
    queue[top] = root
    top += 1
    while head < top:
        if breadth:
            v = queue[head]
            head += 1
        else:
            top -= 1
            v = queue[top]
        for s in range(2):
            b = out[v, s]
            if b < 0:
                continue
            w = ev[b] if eu[b] == v else eu[b]
            if seen[w] == st:
                continue
            seen[w] = st
            pred[w] = b
            wanted = (w == a or w == c) if ends_only else w != a
            if wanted and _free(out, w) > 0:
                return w
            queue[top] = w
            top += 1
    return -1


@nb.njit(cache=True)
def _find_pebble(root, other, out, eu, ev, seen, stamp, pred, stack, breadth):
    """Bring one free pebble to ``root`` (not taken from ``root`` or ``other``).

    Depth first, or breadth first with ``breadth`` (the nearest pebble: cheaper when pebbles
    are gathered again and again in one region, as the cluster labelling does).
    """
    w = _search(root, other, -1, False, out, eu, ev, seen, stamp, pred, stack, breadth)
    if w < 0:
        return False
    x = w
    while x != root:
        c = pred[x]
        y = ev[c] if eu[c] == x else eu[c]
        _move(out, c, y, x)
        x = y
    return True


@nb.njit(cache=True)
def _gather(i, j, want, out, eu, ev, seen, stamp, pred, stack, breadth=False):
    """Gather up to ``want`` pebbles on {i, j} (as many as possible on i first)."""
    while _free(out, i) < PEBBLES and _free(out, i) < want:
        if not _find_pebble(i, j, out, eu, ev, seen, stamp, pred, stack, breadth):
            break
    while _free(out, j) < PEBBLES and _free(out, i) + _free(out, j) < want:
        if not _find_pebble(j, i, out, eu, ev, seen, stamp, pred, stack, breadth):
            break
    return _free(out, i) + _free(out, j)


@nb.njit(cache=True)
def _seed_pair(i, j, g0, g1, seen, st, px, py, lst):
    """Start a lifted search at i (potential 0) and j (potential g) under stamp ``st``.

    Returns the nodes written to ``lst`` (1 when j is i) and whether the two starts agree
    (j is not i, or g is 0).
    """
    seen[i] = st
    px[i] = 0
    py[i] = 0
    lst[0] = i
    if seen[j] == st:
        return 1, g0 == 0 and g1 == 0
    seen[j] = st
    px[j] = g0
    py[j] = g1
    lst[1] = j
    return 2, True


@nb.njit(cache=True)
def _reversed(b, v, vx, vy, npath, oe, otv, otx, oty):
    """Whether bond b out of the lifted node v(vx, vy) is one the overlay path reverses."""
    for t in range(npath):
        if oe[t] == b and otv[t] == v and otx[t] == vx and oty[t] == vy:
            return True
    return False


@nb.njit(cache=True)
def _reach(i, j, g0, g1, out, eu, ev, gx, gy, seen, stamp, px, py, lst):
    """Nodes reachable from i (potential 0) and j (potential g) along the orientation.

    Returns the number of nodes written to ``lst`` and whether every node was reached at one
    potential only (the lifted reach is injective).
    """
    stamp[0] += 1
    st = stamp[0]
    n, ok = _seed_pair(i, j, g0, g1, seen, st, px, py, lst)
    k = 0
    while k < n:
        v = lst[k]
        k += 1
        for s in range(2):
            b = out[v, s]
            if b < 0:
                continue
            w, dx, dy = _step(b, v, eu, ev, gx, gy)
            qx = px[v] + dx
            qy = py[v] + dy
            if seen[w] == st:
                if px[w] != qx or py[w] != qy:
                    ok = False
            else:
                seen[w] = st
                px[w] = qx
                py[w] = qy
                lst[n] = w
                n += 1
    return n, ok


@nb.njit(cache=True)
def _root(comp, x):
    """Root of site x in the union-find forest ``comp`` (paths halved on the way)."""
    while comp[x] != x:
        comp[x] = comp[comp[x]]
        x = comp[x]
    return x


@nb.njit(cache=True)
def _join(comp, a, b):
    """Put sites a and b in one set of ``comp`` (nothing when ``comp`` is empty)."""
    if comp.size == 0:
        return
    ra = _root(comp, a)
    rb = _root(comp, b)
    if ra != rb:
        comp[max(ra, rb)] = min(ra, rb)


@nb.njit(cache=True)
def _mark_out(lst, n, out, over, comp, b):
    """Flag the out-bonds of the nodes ``lst[:n]`` (a circuit closed by bond b) and join them
    with b in ``comp``."""
    for k in range(n):
        v = lst[k]
        for s in range(2):
            if out[v, s] >= 0:
                over[out[v, s]] = True
                _join(comp, out[v, s], b)


@nb.njit(cache=True)
def _lifted_path(i, j, g0, g1, out, eu, ev, gx, gy, stamp, work, path):
    """A directed path in the lift from i(0) or j(g) to another image of i or j with a pebble.

    Writes the path's bonds, forward, into ``path`` (rows: bond, tail node, tail potential x,
    y, head node, head potential x, y) and returns their number (-1 if none was found, which
    cannot happen when only 2 pebbles reach {i, j}). A breadth-first search gives every node
    reached its first potential (a tree); a bond that reaches a node at another potential makes
    two walks on to a pebble that end on two images of the same node, of which at most one is
    the image we start from: that walk, with its loops in the lift cut out, is the path.
    """
    seen, pred, lst, px, py = work[SEEN], work[PRED], work[LIST], work[PX], work[PY]
    seen2, pred2, lst2, onpath = work[SEEN2], work[PRED2], work[LIST2], work[ONPATH]
    stamp[0] += 1
    st = stamp[0]
    seen[i] = st
    px[i], py[i], pred[i] = 0, 0, -1
    seen[j] = st
    px[j], py[j], pred[j] = g0, g1, -1
    lst[0], lst[1] = i, j
    n = 2
    k = 0
    cu, cb, direct = -1, -1, False
    while k < n and not direct:
        v = lst[k]
        k += 1
        for s in range(2):
            b = out[v, s]
            if b < 0:
                continue
            w, dx, dy = _step(b, v, eu, ev, gx, gy)
            qx, qy = px[v] + dx, py[v] + dy
            if seen[w] == st:
                if px[w] != qx or py[w] != qy:
                    if (w == i or w == j) and _free(out, w) > 0:
                        cu, cb, direct = v, b, True
                        break
                    if cu < 0:
                        cu, cb = v, b
            else:
                seen[w] = st
                px[w], py[w], pred[w] = qx, qy, b
                lst[n] = w
                n += 1
    if cu < 0:
        return -1
    w, dx, dy = _step(cb, cu, eu, ev, gx, gy)
    qx, qy = px[cu] + dx, py[cu] + dy
    # the walk on from w to a pebble of i or j (none needed when w is one)
    nP = 0
    x = w
    if not direct:
        x = _search(w, i, j, True, out, eu, ev, seen2, stamp, pred2, lst2, True)
        if x < 0:
            return -1
        y = x
        while y != w:  # the walk's bonds, backward, into LIST2
            lst2[nP] = pred2[y]
            nP += 1
            y = ev[pred2[y]] if eu[pred2[y]] == y else eu[pred2[y]]
        # gain of the walk, and which of the two starts ends on another image
        hx, hy = 0, 0
        y = w
        for t in range(nP - 1, -1, -1):
            y, dx, dy = _step(lst2[t], y, eu, ev, gx, gy)
            hx += dx
            hy += dy
        if qx + hx == px[x] and qy + hy == py[x]:  # via cb it ends on the start image
            cu = -1  # start at w's tree image instead
            qx, qy = px[w], py[w]
    # the tree part: the tree path to cu (then bond cb), or to w
    base = cu if cu >= 0 else w
    stamp[0] += 1
    st3 = stamp[0]
    nt = 0
    y = base
    while True:
        onpath[y] = st3
        nt += 1
        if pred[y] < 0:
            break
        y = ev[pred[y]] if eu[pred[y]] == y else eu[pred[y]]
    # cut the loop: the last node of the walk on that is a tree-part node at its tree potential
    cut_node, cut_at = -1, -1
    y, yx, yy = w, qx, qy
    if onpath[y] == st3 and px[y] == yx and py[y] == yy:
        cut_node, cut_at = y, nP
    for t in range(nP - 1, -1, -1):
        y, dx, dy = _step(lst2[t], y, eu, ev, gx, gy)
        yx += dx
        yy += dy
        if onpath[y] == st3 and px[y] == yx and py[y] == yy:
            cut_node, cut_at = y, t
    # assemble: tree path to the junction, then the rest of the walk
    junction = cut_node if cut_node >= 0 else base
    nt = 0
    y = junction
    while pred[y] >= 0:
        nt += 1
        y = ev[pred[y]] if eu[pred[y]] == y else eu[pred[y]]
    total = nt
    if cut_node < 0 and cu >= 0:
        total += 1  # bond cb
    rest = nP if cut_node < 0 else cut_at
    total += rest
    y = junction
    for t in range(nt - 1, -1, -1):
        b = pred[y]
        z = ev[b] if eu[b] == y else eu[b]
        path[t, 0], path[t, 1], path[t, 2], path[t, 3] = b, z, px[z], py[z]
        path[t, 4], path[t, 5], path[t, 6] = y, px[y], py[y]
        y = z
    r = nt
    if cut_node >= 0:
        y, yx, yy = cut_node, px[cut_node], py[cut_node]
    else:
        if cu >= 0:
            path[r, 0], path[r, 1], path[r, 2], path[r, 3] = cb, cu, px[cu], py[cu]
            path[r, 4], path[r, 5], path[r, 6] = w, qx, qy
            r += 1
        y, yx, yy = w, qx, qy
    for t in range(rest - 1, -1, -1):
        b = lst2[t]
        z, dx, dy = _step(b, y, eu, ev, gx, gy)
        path[r, 0], path[r, 1], path[r, 2], path[r, 3] = b, y, yx, yy
        yx += dx
        yy += dy
        path[r, 4], path[r, 5], path[r, 6] = z, yx, yy
        r += 1
        y = z
    return total


@nb.njit(cache=True)
def _lifted_test(i, j, g0, g1, out, eu, ev, gx, gy, stamp, work, path, over, track, comp, new):
    """Balancedness of the circuit of bond (i, j, g) when only 2 pebbles reach {i, j}.

    Step 1 (:func:`_lifted_path`): a directed path in the lift to another image of i or j
    holding a pebble; its reversal (an overlay: the game itself is not changed) puts a third
    pebble on the pair. Step 2: the reach of the pair in the modified lift meets every node at
    one potential iff the circuit is balanced. Returns True for a balanced circuit; with
    ``track``, flags the circuit's bonds in ``over`` and joins them with the new bond ``new``
    in ``comp``.
    """
    npath = _lifted_path(i, j, g0, g1, out, eu, ev, gx, gy, stamp, work, path)
    if npath < 0:  # cannot happen for an independent set; be conservative
        return False
    seen, lst, px, py, mark = work[SEEN], work[LIST], work[PX], work[PY], work[MARK]
    oe = path[:npath, 0]
    otv, otx, oty = path[:npath, 1], path[:npath, 2], path[:npath, 3]
    ohv, ohx, ohy = path[:npath, 4], path[:npath, 5], path[:npath, 6]
    stamp[0] += 1
    ost = stamp[0]
    for t in range(npath):
        mark[otv[t]] = ost
        mark[ohv[t]] = ost
    # step 2: reach of {i(0), j(g)} in the modified lift, one potential per node
    stamp[0] += 1
    st = stamp[0]
    m, _ = _seed_pair(i, j, g0, g1, seen, st, px, py, lst)
    k = 0
    while k < m:
        v = lst[k]
        k += 1
        vx = px[v]
        vy = py[v]
        for s in range(2):
            b = out[v, s]
            if b < 0:
                continue
            if mark[v] == ost and _reversed(b, v, vx, vy, npath, oe, otv, otx, oty):
                continue
            w, dx, dy = _step(b, v, eu, ev, gx, gy)
            if seen[w] == st:
                if px[w] != vx + dx or py[w] != vy + dy:
                    return False
            else:
                seen[w] = st
                px[w] = vx + dx
                py[w] = vy + dy
                lst[m] = w
                m += 1
        if mark[v] == ost:
            for t in range(npath):
                if ohv[t] == v and ohx[t] == vx and ohy[t] == vy:
                    w = otv[t]
                    if seen[w] == st:
                        if px[w] != otx[t] or py[w] != oty[t]:
                            return False
                    else:
                        seen[w] = st
                        px[w] = otx[t]
                        py[w] = oty[t]
                        lst[m] = w
                        m += 1
    if track:
        _mark_circuit(
            mark, ost, m, lst, out, px, py, npath, oe, otv, otx, oty, ohv, ohx, ohy, over, comp, new
        )
    return True


@nb.njit(cache=True)
def _mark_circuit(
    mark, ost, m, lst, out, px, py, npath, oe, otv, otx, oty, ohv, ohx, ohy, over, comp, new
):
    """Flag the bonds of a balanced circuit: out-bonds of its nodes in the modified lift; join
    them with the bond ``new`` that closed it in ``comp``."""
    for k in range(m):
        v = lst[k]
        for s in range(2):
            b = out[v, s]
            if b < 0:
                continue
            if not (mark[v] == ost and _reversed(b, v, px[v], py[v], npath, oe, otv, otx, oty)):
                over[b] = True
                _join(comp, b, new)
        if mark[v] == ost:
            for t in range(npath):
                if ohv[t] == v and ohx[t] == px[v] and ohy[t] == py[v]:
                    over[oe[t]] = True
                    _join(comp, oe[t], new)


@nb.njit(cache=True)
def play(n_nodes, eu, ev, gx, gy, order, stop_at_wrap, track_circuits, comp):
    """Insert the bonds ``order`` one by one into a fixed-torus pebble game.

    Parameters
    ----------
    n_nodes : int
        Number of nodes N.
    eu, ev, gx, gy : (m,) int64
        Ends and gains of every bond site.
    order : (k,) int64
        Sites to insert, in order.
    stop_at_wrap : bool
        Stop after the first bond whose circuit is unbalanced.
    track_circuits : bool
        Flag the bonds of every fundamental circuit (the overconstrained bonds).
    comp : (m,) or (0,) int64
        With ``track_circuits``, a union-find forest over the sites (``comp[s] = s`` on entry)
        in which every fundamental circuit's bonds are joined: its sets are then the connected
        components of the rigidity matroid of the bonds inserted (two bonds share a set iff some
        circuit holds both; the fundamental circuits of one basis connect exactly these).
        Empty: not tracked.

    Returns
    -------
    status : (m,) int64
        Per site: :data:`UNTESTED`, :data:`INDEPENDENT`, :data:`BALANCED` or :data:`UNBALANCED`.
    first_wrap : int
        Position in ``order`` of the first unbalanced circuit's bond, -1 if none.
    out : (N, 2) int64
        Final pebble slots.
    over : (m,) bool
        Bonds in some fundamental circuit (``track_circuits`` only).
    """
    m = eu.size
    out = -np.ones((n_nodes, 2), np.int64)
    status = np.zeros(m, np.int64)
    over = np.zeros(m, np.bool_)
    work = np.zeros((ROWS, n_nodes), np.int64)
    path = np.zeros((2 * n_nodes + 2, PATH_COLUMNS), np.int64)
    seen, pred, stack, lst = work[SEEN], work[PRED], work[STACK], work[LIST]
    px, py = work[PX], work[PY]
    stamp = np.zeros(1, np.int64)
    first_wrap = -1
    for pos in range(order.size):
        b = order[pos]
        i = eu[b]
        j = ev[b]
        if i == j:  # a bond to the node's own image: a zero row, a one-bond circuit
            status[b] = UNBALANCED
            over[b] = True
        else:
            got = _gather(i, j, ALL_FREE, out, eu, ev, seen, stamp, pred, stack)
            if got == ALL_FREE:
                status[b] = INDEPENDENT
            elif got == ONE_SHORT:
                n, ok = _reach(i, j, gx[b], gy[b], out, eu, ev, gx, gy, seen, stamp, px, py, lst)
                if ok:  # the minimal tight set plus b is balanced: dependent, balanced circuit
                    status[b] = BALANCED
                    if track_circuits:
                        _mark_out(lst, n, out, over, comp, b)
                        over[b] = True
                else:
                    status[b] = INDEPENDENT
            else:
                bal = _lifted_test(
                    i,
                    j,
                    gx[b],
                    gy[b],
                    out,
                    eu,
                    ev,
                    gx,
                    gy,
                    stamp,
                    work,
                    path,
                    over,
                    track_circuits,
                    comp,
                    b,
                )
                if bal:
                    status[b] = BALANCED
                else:
                    status[b] = UNBALANCED
                    if track_circuits:
                        n, _ = _reach(
                            i, j, gx[b], gy[b], out, eu, ev, gx, gy, seen, stamp, px, py, lst
                        )
                        _mark_out(lst, n, out, over, comp, b)
                if track_circuits:
                    over[b] = True
            if status[b] == INDEPENDENT:
                if out[i, 0] < 0:
                    out[i, 0] = b
                elif out[i, 1] < 0:
                    out[i, 1] = b
                elif out[j, 0] < 0:
                    out[j, 0] = b
                else:
                    out[j, 1] = b
        if status[b] == UNBALANCED and first_wrap < 0:
            first_wrap = pos
            if stop_at_wrap:
                break
    return status, first_wrap, out, over


@nb.njit(cache=True)
def _candidate(w, wx, wy, balanced, cst, out, eu, ev, gx, gy, stamp, lab, touched):
    """Search from lifted node w(wx, wy) for a free pebble outside the pinned cluster.

    Returns the number of nodes visited (rows ``TLIST``, ``TPX``, ``TPY`` of ``lab``) if the
    search fails (w is rigidly attached to the cluster), -1 if it finds a pebble (or, in a
    balanced cluster, meets a node at two potentials, which implies one). Two rigid clusters
    share at most one node (else they are one): the search also ends, with -1, on a node of a
    wrapping cluster found before when the cluster cannot take it (it is wrapping itself, or
    already holds a node of that one).
    """
    vst, tpx, tpy, tlst = lab[VISITED], lab[TPX], lab[TPY], lab[TLIST]
    member, mpx, mpy, wrap_of = lab[MEMBER], lab[MPX], lab[MPY], lab[WRAP_OF]
    if wrap_of[w] >= 0 and (not balanced or touched[wrap_of[w]] == cst):
        return -1
    stamp[0] += 1
    st = stamp[0]
    n = 0
    vst[w] = st
    tpx[w] = wx
    tpy[w] = wy
    tlst[n] = w
    n += 1
    k = 0
    while k < n:
        v = tlst[k]
        k += 1
        if _free(out, v) > 0:
            return -1
        for s in range(2):
            b = out[v, s]
            if b < 0:
                continue
            u, dx, dy = _step(b, v, eu, ev, gx, gy)
            ux = tpx[v] + dx
            uy = tpy[v] + dy
            if member[u] == cst:
                if balanced and (mpx[u] != ux or mpy[u] != uy):
                    return -1
                continue
            if vst[u] == st:
                if balanced and (tpx[u] != ux or tpy[u] != uy):
                    return -1
                continue
            if wrap_of[u] >= 0 and (not balanced or touched[wrap_of[u]] == cst):
                return -1
            vst[u] = st
            tpx[u] = ux
            tpy[u] = uy
            tlst[n] = u
            n += 1
    return n


@nb.njit(cache=True)
def label_clusters(n_nodes, eu, ev, gx, gy, sites, out, n_seeds=-1):
    """Rigid-cluster label of every site in ``sites`` (-1 elsewhere), from a finished game.

    Sites are taken in the given order; each one not yet labelled seeds a cluster, up to
    ``n_seeds`` clusters (-1: all; the rest stay -1: labelling only the cluster of one bond, as
    at a threshold, costs one cluster's growth instead of every cluster's). The pebbles
    are gathered on its ends (at most 3). With 3 the cluster is a balanced (finite) rigid body,
    grown in the lift with potentials; with 2 it is the maximal tight set of the torus holding
    the bond (it wraps). A node joins when a search from it finds no free pebble.
    """
    m = eu.size
    labels = -np.ones(m, np.int64)
    start = np.zeros(n_nodes + 1, np.int64)
    for b in sites:
        if eu[b] != ev[b]:
            start[eu[b] + 1] += 1
            start[ev[b] + 1] += 1
    for v in range(n_nodes):
        start[v + 1] += start[v]
    fill = start[:-1].copy()
    adj = np.empty(start[n_nodes], np.int64)
    for b in sites:
        if eu[b] != ev[b]:
            adj[fill[eu[b]]] = b
            fill[eu[b]] += 1
            adj[fill[ev[b]]] = b
            fill[ev[b]] += 1
    lab = np.zeros((LABEL_ROWS, n_nodes), np.int64)
    lab[WRAP_OF] = -1
    tpx, tpy, tlst = lab[TPX], lab[TPY], lab[TLIST]
    member, mpx, mpy, wrap_of = lab[MEMBER], lab[MPX], lab[MPY], lab[WRAP_OF]
    work = np.zeros((ROWS, n_nodes), np.int64)
    seen, pred, stack, lst, px, py = (
        work[SEEN],
        work[PRED],
        work[STACK],
        work[LIST],
        work[PX],
        work[PY],
    )
    failed, fpx, fpy, mem = work[SEEN2], work[PRED2], work[LIST2], work[ONPATH]
    stamp = np.zeros(1, np.int64)
    touched = np.zeros(m + 1, np.int64)
    cst = 0
    nlab = 0
    for b in sites:
        if nlab == n_seeds:
            return labels
        if labels[b] >= 0 or eu[b] == ev[b]:
            continue
        i = eu[b]
        j = ev[b]
        got = _gather(i, j, ONE_SHORT, out, eu, ev, seen, stamp, pred, stack, True)
        n, ok = _reach(i, j, gx[b], gy[b], out, eu, ev, gx, gy, seen, stamp, px, py, lst)
        balanced = got >= ONE_SHORT
        if balanced and not ok:  # not expected: the bond alone
            labels[b] = nlab
            nlab += 1
            continue
        cst += 1
        nm = 0
        for k in range(n):
            v = lst[k]
            member[v] = cst
            mpx[v] = px[v]
            mpy[v] = py[v]
            mem[nm] = v
            nm += 1
            if wrap_of[v] >= 0:
                touched[wrap_of[v]] = cst
        q = 0
        while q < nm:
            v = mem[q]
            q += 1
            for a in range(start[v], start[v + 1]):
                c = adj[a]
                w, dx, dy = _step(c, v, eu, ev, gx, gy)
                if member[w] == cst:
                    continue
                wx = mpx[v] + dx
                wy = mpy[v] + dy
                if failed[w] == cst and (not balanced or (fpx[w] == wx and fpy[w] == wy)):
                    continue
                r = _candidate(w, wx, wy, balanced, cst, out, eu, ev, gx, gy, stamp, lab, touched)
                if r < 0:
                    failed[w] = cst
                    fpx[w] = wx
                    fpy[w] = wy
                    continue
                for k in range(r):
                    u = tlst[k]
                    member[u] = cst
                    mpx[u] = tpx[u]
                    mpy[u] = tpy[u]
                    mem[nm] = u
                    nm += 1
                    if wrap_of[u] >= 0:
                        touched[wrap_of[u]] = cst
        for q in range(nm):
            v = mem[q]
            if not balanced:
                wrap_of[v] = nlab
            for a in range(start[v], start[v + 1]):
                c = adj[a]
                if labels[c] >= 0 or eu[c] != v:
                    continue
                w = ev[c]
                if member[w] != cst:
                    continue
                if balanced and (mpx[w] != mpx[v] + gx[c] or mpy[w] != mpy[v] + gy[c]):
                    continue
                labels[c] = nlab
        if labels[b] < 0:  # not expected: keep every site labelled
            labels[b] = nlab
        nlab += 1
    for b in sites:
        if eu[b] == ev[b]:
            if wrap_of[eu[b]] >= 0:
                labels[b] = wrap_of[eu[b]]
            else:
                labels[b] = nlab
                nlab += 1
    return labels
