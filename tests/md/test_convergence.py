"""Richardson resolution errors (md.convergence) against sequences with a known limit."""

import numpy as np
import pytest

from md.convergence import ORDER_RANGE, resolution_error, richardson


@pytest.mark.parametrize("p", [0.7, 1.0, 1.5, 2.0, 2.9])
@pytest.mark.parametrize("omegas", [(6.0, 5.0, 4.0), (8.0, 5.0, 3.0), (3.0, 4.0, 6.0)])
def test_richardson_recovers_limit_and_order_of_a_power_law(p, omegas):
    """X = X_inf + C Omega^-p at three resolutions, in any order, gives back X_inf and p."""
    x = [12.5 - 7.0 * om ** -p for om in omegas]
    limit, order = richardson(omegas, x)
    assert limit == pytest.approx(12.5, rel=1e-9)
    assert order == pytest.approx(p, rel=1e-8)


@pytest.mark.parametrize("values", [[5.0, 6.0, 5.5],       # the changes differ in sign
                                    [5.0, 5.0, 6.0],       # a zero change
                                    [5.0, 5.1, 6.0],       # order far above the range
                                    [5.0, 6.0, 6.95]])     # order below it
def test_richardson_outside_the_asymptotic_range_is_nan(values):
    limit, order = richardson([4.0, 5.0, 6.0], values)
    assert np.isnan(limit) and np.isnan(order)


def test_order_range_bounds_are_the_accepted_ones():
    lo, hi = ORDER_RANGE
    for p in (lo * 1.01, hi * 0.99):
        assert richardson([4, 5, 6], [1 - om ** -p for om in (4, 5, 6)])[1] == pytest.approx(p)
    for p in (lo * 0.9, hi * 1.1):
        assert np.isnan(richardson([4, 5, 6], [1 - om ** -p for om in (4, 5, 6)])[1])


def test_resolution_error_with_three_resolutions():
    """Per element: the exact error where the sequence is a power law, the first-order
    two-point estimate (flagged) where it is not."""
    om = [6.0, 5.0, 4.0]
    good = [3.0 + 2.0 * o ** -1.3 for o in om]          # error of the finest: 2 * 6^-1.3
    bad = [7.0, 6.0, 7.5]
    err, asym = resolution_error(om, np.stack([good, bad], axis=1))
    assert asym.tolist() == [True, False]
    assert err[0] == pytest.approx(2.0 * 6.0 ** -1.3, rel=1e-9)
    assert err[1] == pytest.approx(1.0 / (6.0 / 5.0 - 1.0))


def test_settled_sequence_keeps_the_first_order_error():
    """Changes of either sign below 1 % of the value (the lattice's noise, as at half-filled
    pores): counted as converged, with the first-order two-point error."""
    err, asym = resolution_error([6.0, 5.0, 4.0], np.array([[39.45, 30.0], [39.56, 33.0],
                                                            [39.63, 31.0]]))
    assert asym.tolist() == [True, False]
    assert err[0] == pytest.approx(0.11 / 0.2)
    assert err[1] == pytest.approx(3.0 / 0.2)


def test_richardson_wins_over_the_settled_rule():
    """A power law whose changes are below 1 % still gets its Richardson error (the
    first-order one would be too small for an order below 1)."""
    om = [6.0, 5.0, 4.0]
    x = np.array([[3.0 - 0.2 * o ** -0.6] for o in om])
    assert np.all(np.abs(np.diff(x[:, 0])) < 0.01 * x[0, 0])
    err, asym = resolution_error(om, x)
    assert asym[0]
    assert err[0] == pytest.approx(0.2 * 6.0 ** -0.6, rel=1e-8)


def test_resolution_independent_values_have_no_error():
    """One value at every resolution (an uncemented sample): error zero, not flagged."""
    err, asym = resolution_error([6.0, 5.0, 4.0], np.full((3, 2), 4.2))
    assert err.tolist() == [0.0, 0.0] and asym.all()


def test_resolution_error_with_two_resolutions_is_first_order():
    """Exact for a first-order sequence; never flagged asymptotic."""
    om = [4.0, 3.0]
    x = np.array([[2.0 + 3.0 / o for o in om]]).T
    err, asym = resolution_error(om, x)
    assert err[0] == pytest.approx(3.0 / 4.0)
    assert not asym.any()


@pytest.mark.parametrize("omegas,shape", [([4.0], (1,)), ([3.0, 4.0], (2,)),
                                          ([4.0, 3.0, 3.0], (3,)), ([4.0, 0.5], (2,)),
                                          ([4.0, 3.0], (3,))])
def test_resolution_error_refuses_bad_resolutions(omegas, shape):
    with pytest.raises(ValueError, match="resolution|omegas"):
        resolution_error(omegas, np.ones(shape))
