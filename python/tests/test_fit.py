import json

import numpy as np
import pytest

import mspline
from conftest import TSPLINE_FIT_ARGUMENTS
from helpers import assert_same_figures, counts_alongside, diagonal, without_timings


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
    refinement = [r for r in report["refinement"] if "repair_of" not in r]
    assert 1 <= len(refinement) <= TSPLINE_FIT_ARGUMENTS["max_refinements"] + 1
    assert report["refinement"][:len(refinement)] == refinement
    for r in report["refinement"][len(refinement):]:
        assert r["remedy"] in ("split", "stiffen", "split around", "stiffen around")
        assert 0 <= r["repair_of"] < len(report["refinement"])
    kept = [r for r in report["refinement"] if r["kept"]]
    assert len(kept) == 1
    assert kept[0]["control_points"] == report["control_points"]
    assert kept[0]["folds"] == report["quality"]["folds"]["total"]


def test_the_fit_report_has_the_figures_of_mspline_fit_json(fitted, eight_msp):
    report = fitted[0].fit_report
    expected = json.loads(eight_msp.with_suffix(".json").read_text())
    shared = set(report) & set(expected) - {"stage_seconds", "refinement", "quality"}
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
    # The whole `quality` object, as the CLI prints it (the same builder).
    assert_same_figures(without_timings(report["quality"]), without_timings(expected["quality"]),
                        rel=1e-12, where="quality")


def test_quality_measures_what_the_fit_reported(fitted, eight):
    model, _ = fitted
    quality = model.quality(*eight)
    report = model.fit_report
    distances = quality["distances"]
    assert quality["with_scan"] is True
    assert distances["scan_to_surface"]["rms"] == pytest.approx(report["rms_error"], rel=1e-9)
    assert distances["scan_to_surface"]["max"] == pytest.approx(report["max_error"], rel=1e-9)
    assert distances["surface_to_scan"]["max"] == pytest.approx(
        report["max_error_surface_to_scan"], rel=1e-9)
    assert_same_figures(without_timings(quality), without_timings(report["quality"]), rel=1e-9,
                        where="quality")


def test_quality_reports_folds_smoothness_and_regularity(fitted, eight):
    model, _ = fitted
    quality = model.quality(*eight)
    folds = quality["folds"]
    assert folds["total"] == model.fit_report["folds"] >= 0
    assert 0 <= folds["fraction"] <= 1
    assert folds["triangles"] > 0
    smoothness = quality["smoothness"]
    coarse, fine = smoothness["coarse"], smoothness["fine"]
    assert fine["resolution"] == 2 * coarse["resolution"]
    for dihedral in (coarse, fine):
        assert dihedral["pairs"] > 0
        assert 0 <= dihedral["p50"] <= dihedral["p99"] <= dihedral["p99_9"] <= dihedral["max"]
        assert dihedral["max"] <= 180
    # A smooth fit's dihedral angles shrink as the tessellation refines.
    assert fine["p99"] < coarse["p99"]
    assert smoothness["p99_ratio"] == pytest.approx(coarse["p99"] / fine["p99"], rel=1e-9)
    regularity = quality["regularity"]
    assert regularity["samples"] > 0 and regularity["median_jacobian"] > 0
    assert 0 < regularity["min_relative_jacobian"] <= 1
    assert quality["seconds"] > 0


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
    with pytest.raises(ValueError, match="corner valence must be 2 or 3"):
        mspline.fit(V, F, min_corner_valence=4)


def test_an_invalid_mesh_is_a_value_error_naming_it(eight):
    V, F = eight
    with pytest.raises(ValueError, match="my scan"):
        mspline.fit(V, np.vstack([F, F[:1]]), name="my scan")
    with pytest.raises(ValueError, match="my scan"):
        mspline.fit(V, F + len(V), name="my scan")
