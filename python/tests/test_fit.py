import json

import numpy as np
import pytest

import mspline
from conftest import TSPLINE_FIT_ARGUMENTS
from helpers import counts_alongside, diagonal


@pytest.fixture(scope="module")
def fitted(eight):
    calls = []
    model = mspline.fit(*eight, progress=lambda stage, fraction: calls.append((stage, fraction)),
                        **TSPLINE_FIT_ARGUMENTS)
    return model, calls


def test_python_fit_gives_the_control_points_of_mspline_fit(fitted, eight_msp):
    model, _ = fitted
    reference = mspline.load(eight_msp)
    assert model.kind == reference.kind == "tspline"
    assert model.control_points.shape == reference.control_points.shape
    np.testing.assert_allclose(model.control_points, reference.control_points, rtol=0,
                               atol=1e-12 * diagonal(reference.control_points))


def test_the_fit_report_tells_how_the_fit_went(fitted):
    model, _ = fitted
    report = model.fit_report
    budget = TSPLINE_FIT_ARGUMENTS["max_control"]
    assert report["control_points"] == len(model.control_points) <= budget
    assert report["within_budget"] is True
    assert isinstance(report["reached_tolerance"], bool)
    for key in ("rms_error", "max_error", "rms_error_surface_to_scan",
                "max_error_surface_to_scan"):
        assert 0 < report[key] < 0.1
    assert report["rms_error"] <= report["max_error"]
    assert 1 <= len(report["refinement"]) <= TSPLINE_FIT_ARGUMENTS["max_refinements"] + 1
    assert report["refinement"][-1]["control_points"] == report["control_points"]


def test_the_fit_report_has_the_figures_of_mspline_fit_json(fitted, eight_msp):
    report = fitted[0].fit_report
    expected = json.loads(eight_msp.with_suffix(".json").read_text())
    shared = set(report) & set(expected) - {"stage_seconds", "refinement"}
    assert {"control_points", "rms_error", "max_error_surface_to_scan", "reached_tolerance",
            "rounds", "flatten"} <= shared
    for key in shared:
        if isinstance(expected[key], (float, dict)):
            assert report[key] == pytest.approx(expected[key], rel=1e-12), key
        else:
            assert report[key] == expected[key], key
    for ours, theirs in zip(report["refinement"], expected["refinement"], strict=True):
        assert ours["control_points"] == theirs["control_points"]
        assert ours["rms_error"] == pytest.approx(theirs["rms_error"], rel=1e-12)


def test_quality_measures_what_the_fit_reported(fitted, eight):
    model, _ = fitted
    quality = model.quality(*eight)
    for key in ("rms_error", "max_error", "rms_error_surface_to_scan",
                "max_error_surface_to_scan"):
        assert quality[key] == pytest.approx(model.fit_report[key], rel=1e-9)


def test_progress_is_called_with_a_stage_and_a_fraction(fitted):
    _, calls = fitted
    assert len(calls) > 3
    assert all(isinstance(stage, str) and stage for stage, _ in calls)
    assert all(0.0 <= fraction <= 1.0 for _, fraction in calls)


def test_an_error_in_progress_stops_the_fit(eight):
    def progress(stage, fraction):
        raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        mspline.fit(*eight, progress=progress, **TSPLINE_FIT_ARGUMENTS)


def test_another_thread_keeps_running_during_a_fit(eight):
    assert counts_alongside(lambda: mspline.fit(*eight, **TSPLINE_FIT_ARGUMENTS)) > 10000


def test_fit_checks_its_arguments(eight):
    V, F = eight
    with pytest.raises(ValueError, match="shape"):
        mspline.fit(V[:, :2], F)
    with pytest.raises(ValueError, match="shape"):
        mspline.fit(V, F.ravel())
    with pytest.raises(TypeError, match="integers"):
        mspline.fit(V, F.astype(float))
    with pytest.raises(TypeError, match="real numbers"):
        mspline.fit(V.astype(str), F)
    with pytest.raises(ValueError, match="nurbs"):
        mspline.fit(V, F, kind="nurbs")
    with pytest.raises(TypeError, match="progress"):
        mspline.fit(V, F, progress=3)


def test_an_invalid_mesh_is_a_value_error_naming_it(eight):
    V, F = eight
    with pytest.raises(ValueError, match="my scan"):
        mspline.fit(V, np.vstack([F, F[:1]]), name="my scan")
    with pytest.raises(ValueError, match="my scan"):
        mspline.fit(V, F + len(V), name="my scan")
