import numpy as np
import pytest

import mspline


def test_read_mesh_gives_float_vertices_and_integer_triangles(data_dir):
    V, F = mspline.read_mesh(data_dir / "eight.off")
    assert V.dtype == np.float64 and V.ndim == 2 and V.shape[1] == 3
    assert np.issubdtype(F.dtype, np.integer) and F.ndim == 2 and F.shape[1] == 3
    # eight.off: a closed surface of genus 2, V - E + F = -2 with E = 3F / 2.
    assert len(V) - len(F) // 2 == -2
    assert F.min() == 0 and F.max() == len(V) - 1


def test_read_mesh_matches_the_file(data_dir):
    path = data_dir / "eight.off"
    lines = [line.split() for line in path.read_text().splitlines()
             if line.strip() and not line.startswith("#")]
    assert lines[0] == ["OFF"]
    n, m = int(lines[1][0]), int(lines[1][1])
    V, F = mspline.read_mesh(str(path))
    np.testing.assert_array_equal(V, np.array(lines[2:2 + n], dtype=float))
    np.testing.assert_array_equal(F, np.array(lines[2 + n:2 + n + m], dtype=int)[:, 1:])


def test_a_missing_file_is_a_value_error_naming_it(tmp_path):
    missing = tmp_path / "nowhere.off"
    with pytest.raises(ValueError, match="nowhere.off"):
        mspline.read_mesh(missing)


def test_an_invalid_mesh_is_a_value_error_naming_it(tmp_path):
    # Three triangles on one edge: not a manifold.
    path = tmp_path / "fin.off"
    path.write_text("OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n"
                    "3 0 1 2\n3 1 0 3\n3 0 1 4\n")
    with pytest.raises(ValueError, match="fin.off"):
        mspline.read_mesh(path)
