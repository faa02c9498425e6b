"""Box, minimum image and neighbour lists: cell-list kernels against brute force."""

import doctest
import itertools

import numpy as np
import pytest

from md import _kernels_neighbors as kernels
from md import neighbors, space
from md.neighbors import NeighborList, brute_force_pairs, build_neighbors, needs_rebuild
from md.space import Box, minimum_image, wrap

MM = 1e-3
BOX = Box(12 * MM, 10 * MM, 0.0, 15 * MM)


def pack(rng, n, box=BOX, edge_fraction=0.4):
    """Random polydisperse spheres (r 0.9–1.1 mm), many of them close to the boundaries.

    A share ``edge_fraction`` sits within 1.5 mm of a periodic face (some outside [0, L), as
    unwrapped positions are) or of a z wall (some a little beyond it, as overlapping a wall).
    """
    x = rng.uniform((0.0, 0.0, box.lz_min), (box.lx, box.ly, box.lz_max), size=(n, 3))
    edge = rng.random(n) < edge_fraction
    axis = rng.integers(0, 3, size=n)
    side = rng.integers(0, 2, size=n)
    offset = rng.uniform(-0.3 * MM, 1.5 * MM, size=n)
    low = np.array([0.0, 0.0, box.lz_min])
    high = np.array([box.lx, box.ly, box.lz_max])
    for i in np.flatnonzero(edge):
        a = axis[i]
        x[i, a] = low[a] + offset[i] if side[i] == 0 else high[a] - offset[i]
    r = rng.uniform(0.9 * MM, 1.1 * MM, size=n)
    return x, r


def as_set(pairs):
    return {tuple(p) for p in np.asarray(pairs).tolist()}


def forced_grid_pairs(x, r, box, skin, shape, capacity=None, kernel=kernels.neighbor_pairs,
                      cells=kernels.cell_list):
    """Run the kernels on a chosen grid (cells as large as the shape allows)."""
    z0 = x[:, 2].min()
    height = x[:, 2].max() - z0
    size = (box.lx / shape[0], box.ly / shape[1], max(height / shape[2], 2 * r.max() + skin))
    cell_of, start, order = cells(x, box.lx, box.ly, z0, shape, size)
    capacity = len(x) ** 2 if capacity is None else capacity
    pairs = np.empty((capacity, 2), np.int32)
    count = kernel(x, r, box.lx, box.ly, skin, shape, cell_of, start, order, pairs)
    return count, pairs


# --- space -----------------------------------------------------------------------------------

@pytest.mark.parametrize("fields, name", [
    ((0.0, 1.0, 0.0, 1.0), "lx"), ((1.0, -1.0, 0.0, 1.0), "ly"),
    ((np.nan, 1.0, 0.0, 1.0), "lx"), ((1.0, 1.0, np.inf, 1.0), "lz_min"),
    ((1.0, 1.0, 1.0, 1.0), "lz_max"), ((1.0, 1.0, 0.0, "top"), "lz_max"),
])
def test_box_rejects_bad_fields(fields, name, expect_value_error):
    expect_value_error(lambda: Box(*fields), name)


def test_box_is_frozen_and_float():
    box = Box(1, 2, -1, 3)
    assert (box.lx, box.ly, box.lz, box.volume) == (1.0, 2.0, 4.0, 8.0)
    assert isinstance(box.lx, float)
    with pytest.raises(AttributeError):
        box.lx = 3.0


def test_minimum_image_and_wrap(rng):
    box = Box(1.0, 2.0, 0.0, 1.0)
    d = rng.uniform(-5.0, 5.0, size=(200, 3))
    m = minimum_image(d, box)
    assert np.all(np.abs(m[:, 0]) <= 0.5) and np.all(np.abs(m[:, 1]) <= 1.0)
    np.testing.assert_array_equal(m[:, 2], d[:, 2])
    # The shift is a whole number of periods.
    for axis, length in ((0, box.lx), (1, box.ly)):
        periods = (d[:, axis] - m[:, axis]) / length
        np.testing.assert_allclose(periods, np.round(periods), rtol=0, atol=1e-12)
    w = wrap(d, box)
    assert np.all((w[:, 0] >= 0) & (w[:, 0] < 1.0) & (w[:, 1] >= 0) & (w[:, 1] < 2.0))
    np.testing.assert_allclose(minimum_image(w - d, box), 0.0, rtol=0, atol=1e-12)
    # A value that rounds to the period folds to 0, not to L.
    assert wrap([[-1e-300, -1e-17, 0.0]], box)[0, :2].tolist() == [0.0, 0.0]
    with pytest.raises(ValueError, match=r"\bd\b"):
        minimum_image(np.zeros((4, 2)), box)
    with pytest.raises(TypeError, match=r"\bbox\b"):
        wrap(np.zeros((4, 3)), (1.0, 1.0, 0.0, 1.0))


# --- neighbour list against brute force --------------------------------------------------------

@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("skin", [0.0, 0.02 * MM, 0.2 * MM, 1.0 * MM])
def test_neighbor_list_equals_brute_force(seed, skin):
    x, r = pack(np.random.default_rng(seed), 300)
    nl = build_neighbors(x, r, BOX, skin)
    expected = brute_force_pairs(x, r, BOX, skin)
    assert expected.shape[0] > 0
    assert as_set(nl.pairs) == as_set(expected)
    np.testing.assert_array_equal(nl.pairs, expected)  # same lexicographic order too


def test_pairs_layout(rng):
    x, r = pack(rng, 200)
    nl = build_neighbors(x, r, BOX, 0.1 * MM)
    p = nl.pairs
    assert p.dtype == np.int32 and p.ndim == 2 and p.shape[1] == 2 and nl.n_pairs == len(p)
    assert np.all(p[:, 0] < p[:, 1])
    keys = p[:, 0].astype(np.int64) * len(x) + p[:, 1]
    assert np.all(np.diff(keys) > 0)  # lexicographic, no duplicates
    assert not p.flags.writeable and not nl.reference_positions.flags.writeable
    # The reference is a copy: moving the caller's array does not move it.
    x[:] += 1.0
    assert not np.array_equal(nl.reference_positions, x)


def test_pairs_across_every_boundary():
    """Touching pairs straddle the x, y faces and a corner; one sits beyond a z wall."""
    box = Box(10 * MM, 10 * MM, 0.0, 10 * MM)
    x = np.array([[0.2, 5.0, 5.0], [9.7, 5.0, 5.0],      # across x = 0 / lx
                  [5.0, 0.1, 2.0], [5.0, 9.95, 2.0],     # across y
                  [0.3, 0.3, 8.0], [9.8, 9.8, 8.0],      # across the corner
                  [5.0, 5.0, -0.5], [5.0, 5.0, 1.3],     # one below the bottom wall
                  [-9.8, 25.0, 5.0], [0.1, 4.9, 5.0]]) * MM  # 8: an unwrapped image of 0
    r = np.full(len(x), 1.0 * MM)
    expected = brute_force_pairs(x, r, box, 0.0)
    assert {(0, 1), (2, 3), (4, 5), (6, 7), (0, 8), (1, 8)} <= as_set(expected)
    np.testing.assert_array_equal(build_neighbors(x, r, box, 0.0).pairs, expected)


@pytest.mark.parametrize("lx, ly", [(4.5 * MM, 4.5 * MM), (7 * MM, 4.5 * MM),
                                    (7 * MM, 11 * MM), (4.5 * MM, 30 * MM)])
def test_small_boxes_with_one_or_two_cells(lx, ly):
    """Large skin in a narrow box: 1 or 2 cells along x or y must not double-count pairs."""
    box = Box(lx, ly, 0.0, 20 * MM)
    x, r = pack(np.random.default_rng(7), 60, box)
    skin = 1.5 * MM
    nl = build_neighbors(x, r, box, skin)
    np.testing.assert_array_equal(nl.pairs, brute_force_pairs(x, r, box, skin))


def test_every_grid_gives_the_same_pairs(rng):
    """Any grid with cells >= the cutoff, from 1 x 1 x 1 up to the finest, finds the same list."""
    x, r = pack(rng, 120)
    skin = 0.3 * MM
    expected = brute_force_pairs(x, r, BOX, skin)
    cutoff = 2 * r.max() + skin
    finest = [int(BOX.lx // cutoff), int(BOX.ly // cutoff),
              int((x[:, 2].max() - x[:, 2].min()) // cutoff)]
    for shape in itertools.product(*[sorted({1, 2, 3, n}) for n in finest]):
        count, pairs = forced_grid_pairs(x, r, BOX, skin, shape)
        np.testing.assert_array_equal(pairs[:count], expected, err_msg=f"grid {shape}")


def test_dilute_tall_box_caps_the_grid():
    """A few grains in a tall box: the grid is capped near 4 cells per particle, still exact."""
    box = Box(0.5, 0.4, 0.0, 1.0)
    rng = np.random.default_rng(3)
    x = rng.uniform((0, 0, 0), (0.5, 0.4, 1.0), size=(40, 3))
    x[20:] = x[:20] + rng.normal(scale=1.0 * MM, size=(20, 3))  # some close pairs
    r = rng.uniform(0.9 * MM, 1.1 * MM, size=40)
    shape, size = neighbors._cell_grid(box, x[:, 2].min(), x[:, 2].max(), 2.2 * MM, 40)
    assert np.prod(shape) <= 4 * 40 and min(size) >= 2.2 * MM
    nl = build_neighbors(x, r, box, 0.0)
    assert nl.n_pairs > 0
    np.testing.assert_array_equal(nl.pairs, brute_force_pairs(x, r, box, 0.0))


@pytest.mark.parametrize("n", [0, 1])
def test_empty_and_single_particle(n):
    x, r = np.zeros((n, 3)), np.full(n, MM)
    for pairs in (build_neighbors(x, r, BOX, MM).pairs, brute_force_pairs(x, r, BOX, MM)):
        assert pairs.shape == (0, 2) and pairs.dtype == np.int32


# --- overflow -----------------------------------------------------------------------------------

@pytest.mark.parametrize("capacity", [0, 1, 17])
def test_overflowing_buffer_gives_the_same_list(rng, capacity):
    x, r = pack(rng, 200)
    skin = 0.5 * MM
    expected = brute_force_pairs(x, r, BOX, skin)
    assert len(expected) > capacity
    nl = build_neighbors(x, r, BOX, skin, capacity=capacity)
    np.testing.assert_array_equal(nl.pairs, expected)


def test_kernel_reports_the_true_count_on_overflow(rng):
    x, r = pack(rng, 100)
    skin = 0.5 * MM
    expected = brute_force_pairs(x, r, BOX, skin)
    count, pairs = forced_grid_pairs(x, r, BOX, skin, (3, 3, 3), capacity=5)
    assert count == len(expected) > 5
    assert as_set(pairs) <= as_set(expected)  # what was written is right, just incomplete


# --- numba kernels against their plain-Python twins ----------------------------------------------

@pytest.mark.parametrize("shape", [(1, 1, 1), (2, 2, 1), (3, 2, 2), (4, 3, 2)])
def test_kernels_equal_python_twins(shape):
    box = Box(9 * MM, 7 * MM, 0.0, 8 * MM)
    x, r = pack(np.random.default_rng(11), 14, box)
    x[0, 0] -= 9 * MM  # an unwrapped position
    skin = 0.1 * MM
    grid_args = (x, box.lx, box.ly, x[:, 2].min(), shape, (box.lx / shape[0],
                 box.ly / shape[1], max(2.3 * MM, np.ptp(x[:, 2]) / shape[2])))
    for fast, slow in zip(kernels.cell_list(*grid_args), kernels.cell_list.py_func(*grid_args)):
        np.testing.assert_array_equal(fast, slow)
    c_fast, p_fast = forced_grid_pairs(x, r, box, skin, shape)
    c_slow, p_slow = forced_grid_pairs(x, r, box, skin, shape,
                                       kernel=kernels.neighbor_pairs.py_func,
                                       cells=kernels.cell_list.py_func)
    assert c_fast == c_slow
    np.testing.assert_array_equal(p_fast[:c_fast], p_slow[:c_slow])
    np.testing.assert_array_equal(p_fast[:c_fast], brute_force_pairs(x, r, box, skin))
    x_moved = x + 0.06 * MM
    for limit in (0.05 * MM, 0.2 * MM):
        args = (x_moved, x, box.lx, box.ly, limit)
        assert kernels.moved_beyond(*args) == kernels.moved_beyond.py_func(*args)


# --- needs_rebuild ------------------------------------------------------------------------------

def test_needs_rebuild_threshold_is_half_the_skin(rng):
    x, r = pack(rng, 50)
    skin = 0.2 * MM
    nl = build_neighbors(x, r, BOX, skin)
    assert not needs_rebuild(nl, x, BOX)
    direction = np.array([0.6, -0.0, 0.8])
    for fraction, expected in ((0.49, False), (0.51, True)):
        moved = x.copy()
        moved[17] += fraction * skin * direction
        assert needs_rebuild(nl, moved, BOX) is expected


def test_needs_rebuild_uses_the_minimum_image(rng):
    """Wrapping positions into the box is not a move."""
    x, r = pack(rng, 80)
    nl = build_neighbors(x, r, BOX, 0.1 * MM)
    assert np.any(x[:, :2] < 0) or np.any(x[:, 0] >= BOX.lx)  # the pack has unwrapped grains
    assert not needs_rebuild(nl, wrap(x, BOX), BOX)
    assert not needs_rebuild(nl, x + [BOX.lx, -2 * BOX.ly, 0.0], BOX)


def test_needs_rebuild_other_cases(rng):
    x, r = pack(rng, 30)
    nl = build_neighbors(x, r, BOX, 0.0)
    assert not needs_rebuild(nl, x, BOX)  # skin 0: only no motion at all keeps it
    moved = x.copy()
    moved[3, 2] += 1e-12
    assert needs_rebuild(nl, moved, BOX)
    nl = build_neighbors(x, r, BOX, 0.1 * MM)
    moved = x.copy()
    moved[5, 1] = np.nan
    assert needs_rebuild(nl, moved, BOX)  # not finite: rebuild (which then raises)
    assert needs_rebuild(nl, x, Box(BOX.lx * 1.01, BOX.ly, 0.0, BOX.lz_max))  # new period
    assert not needs_rebuild(nl, x, Box(BOX.lx, BOX.ly, 1 * MM, 14 * MM))  # walls don't matter
    with pytest.raises(ValueError, match=r"\bx\b"):
        needs_rebuild(nl, x[:-1], BOX)
    with pytest.raises(TypeError, match=r"\bnl\b"):
        needs_rebuild(nl.pairs, x, BOX)


def test_list_still_holds_every_contact_until_rebuild(rng):
    """The Verlet guarantee: moves up to skin/2 create no contact missing from the list."""
    x, r = pack(rng, 300)
    skin = 0.2 * MM
    listed = as_set(build_neighbors(x, r, BOX, skin).pairs)
    for _ in range(5):
        step = rng.normal(size=x.shape)
        step *= (0.4999 * skin * rng.random(len(x)) / np.linalg.norm(step, axis=1))[:, None]
        contacts = as_set(brute_force_pairs(x + step, r, BOX, 0.0))
        assert contacts and contacts <= listed


# --- input checking -----------------------------------------------------------------------------

def _bad_inputs():
    x, r = pack(np.random.default_rng(5), 10)
    x_nan = x.copy()
    x_nan[2, 1] = np.nan
    r_neg = r.copy()
    r_neg[4] = -r_neg[4]
    r_inf = r.copy()
    r_inf[0] = np.inf
    ok = {"x": x, "r": r, "box": BOX, "skin": 0.1 * MM}
    return [
        (dict(ok, x=x[:, :2]), "x"), (dict(ok, x=x[0]), "x"), (dict(ok, x=x_nan), "x"),
        (dict(ok, r=r[:-1]), "r"), (dict(ok, r=r_neg), "r"), (dict(ok, r=r_inf), "r"),
        (dict(ok, r=np.zeros(10)), "r"),
        (dict(ok, skin=-1e-6), "skin"), (dict(ok, skin=np.nan), "skin"),
        (dict(ok, skin="thin"), "skin"),
        (dict(ok, box=Box(3.5 * MM, 20 * MM, 0.0, 1.0)), "box"),
        (dict(ok, box=Box(20 * MM, 3.5 * MM, 0.0, 1.0)), "box"),
    ]


@pytest.mark.parametrize("kwargs, name", _bad_inputs())
@pytest.mark.parametrize("function", [build_neighbors, brute_force_pairs])
def test_bad_inputs_name_the_argument(function, kwargs, name, expect_value_error):
    expect_value_error(lambda: function(**kwargs), name)


def test_bad_capacity_and_box_type(expect_value_error):
    x, r = pack(np.random.default_rng(5), 10)
    for capacity in (-1, 2.5, True):
        expect_value_error(lambda c=capacity: build_neighbors(x, r, BOX, 0.0, capacity=c),
                           "capacity")
    with pytest.raises(TypeError, match=r"\bbox\b"):
        build_neighbors(x, r, (1.0, 1.0, 0.0, 1.0), 0.0)


def test_neighbor_list_is_frozen(rng):
    x, r = pack(rng, 10)
    nl = build_neighbors(x, r, BOX, 0.0)
    assert isinstance(nl, NeighborList)
    with pytest.raises(AttributeError):
        nl.skin = 1.0


@pytest.mark.parametrize("module", [space, neighbors])
def test_docstring_examples(module):
    """md is not in pytest's doctest paths, so its examples run here."""
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.attempted > 0 and result.failed == 0
