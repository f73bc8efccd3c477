import math

import numpy as np
import pytest

import mspline


@pytest.fixture(scope="module")
def flat_eight(eight):
    calls = []
    flat = mspline.flatten(*eight, quantize=True,
                           progress=lambda stage, fraction: calls.append((stage, fraction)))
    return flat, calls


def edge_lengths(flat):
    """Per face side (corner k to corner k + 1): its vertices and its length in the layout."""
    F, uvs = flat["F"], flat["uvs"]
    sides = {}
    for k in range(3):
        length = np.linalg.norm(uvs[:, (k + 1) % 3] - uvs[:, k], axis=1)
        for a, b, d in zip(F[:, k], F[:, (k + 1) % 3], length):
            sides.setdefault((min(a, b), max(a, b)), []).append(d)
    return sides


def test_a_flattening_of_a_closed_genus_2_surface(flat_eight, eight):
    flat, _ = flat_eight
    V, F = eight
    assert flat["converged"] is True
    assert flat["flipped_triangles"] == 0
    # eight.off degenerates under the flow: intrinsic flips, and the surface laid out is the
    # common subdivision, whose first vertices are the input's.
    assert flat["flips"] > 0
    np.testing.assert_array_equal(flat["V"][:len(V)], V)
    assert len(flat["F"]) > len(F) and flat["uvs"].shape == (len(flat["F"]), 3, 2)
    assert flat["uvs"].dtype == np.float64
    # Gauss-Bonnet: the cones carry all the curvature, 2 pi (2 - 2g) = -4 pi; quantized, each a
    # multiple of pi / 2.
    curvatures = np.array([c for _, c in flat["cones"]])
    assert curvatures.sum() == pytest.approx(-4 * math.pi, abs=1e-9)
    np.testing.assert_allclose(curvatures / (math.pi / 2), np.round(curvatures / (math.pi / 2)),
                               atol=1e-9)


def test_the_layout_is_one_flat_metric(flat_eight):
    flat, _ = flat_eight
    uvs = flat["uvs"]
    e1, e2 = uvs[:, 1] - uvs[:, 0], uvs[:, 2] - uvs[:, 0]
    assert (e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] > 0).all()
    # Both faces along an edge give it the same length, wherever the cut put them in the plane.
    sides = edge_lengths(flat)
    assert all(len(lengths) == 2 for lengths in sides.values())
    for lengths in sides.values():
        assert lengths[0] == pytest.approx(lengths[1], rel=1e-8)


def test_flatten_reports_progress(flat_eight):
    _, calls = flat_eight
    assert calls and all(isinstance(stage, str) and 0.0 <= f <= 1.0 for stage, f in calls)


def test_a_torus_flattens_without_cones(data_dir):
    flat = mspline.flatten(*mspline.read_mesh(data_dir / "knot1.off"), cones=[])
    assert flat["converged"] is True and flat["cones"] == []
    assert flat["cone_placement"] == "" and flat["reached_max_cones"] is False


def test_automatic_cones_are_placed_again_where_handles_cannot_be_quantized(data_dir):
    # knot.off: the 8 cones placed first leave handle rotations that cannot be quantized.
    flat = mspline.flatten(*mspline.read_mesh(data_dir / "knot.off"), quantize=True)
    assert flat["converged"] is True
    assert flat["rejected_cone_counts"] and flat["rejected_cone_counts"][0] == 8
    assert len(flat["cones"]) not in flat["rejected_cone_counts"]
    # The set kept was asked for by count.
    assert "reached the requested count" in flat["cone_placement"]
    assert flat["reached_max_cones"] is False


def test_flatten_checks_its_arguments(eight):
    V, F = eight
    with pytest.raises(ValueError, match="scheme"):
        mspline.flatten(V, F, scheme="euclid")
    with pytest.raises(ValueError, match="boundary"):
        mspline.flatten(V, F, boundary="round")
    with pytest.raises(ValueError):
        mspline.flatten(V, F, cones=[(len(V), 1.0)])
    with pytest.raises(TypeError):
        mspline.flatten(V, F, cones=[("a", 1.0)])
    with pytest.raises(TypeError, match="progress"):
        mspline.flatten(V, F, progress="yes")
    with pytest.raises(ValueError, match="shape"):
        mspline.flatten(V.T, F)
