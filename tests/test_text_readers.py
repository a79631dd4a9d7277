"""The plain text height matrix as people write it (probe h53, findings 8 and 9).

Semicolons, decimal commas and tabs read the same numbers as the whitespace matrix; a short row
or a bad value is refused naming the file's own line (comments counted) and what is wrong there,
not numpy's row of the data; a header with ``# Width:`` but no ``# Height:`` says which is
missing, and a ``--size`` that contradicts the width it gives is refused.
"""

import numpy as np
import pytest

from halfspace_calib import topography as S
from halfspace_calib.cli import main
from halfspace_calib.topography._formats import load_matrix

HEAD = "# Width: 8.00 µm\n# Height: 4.00 µm\n# Value units: m\n"
H = np.random.default_rng(5).normal(0.0, 2e-8, (4, 8)).round(12)


def _rows(sep, comma=False):
    cells = [[f"{v:.6e}" for v in row] for row in H]
    if comma:
        cells = [[c.replace(".", ",") for c in row] for row in cells]
    return "".join(sep.join(row) + "\n" for row in cells)


@pytest.mark.parametrize(
    "sep, comma",
    [
        ("\t", False),
        (" ", False),
        (",", False),
        (";", False),
        (";", True),
        ("\t", True),
        ("  ", True),
    ],
)
def test_separators_and_decimal_commas_read_the_same_matrix(tmp_path, sep, comma):
    f = tmp_path / "m.txt"
    f.write_text(HEAD + _rows(sep, comma), encoding="utf-8")
    h = load_matrix(f, "m")
    assert h.shape == (4, 8) and np.array_equal(
        h, np.array([[float(f"{v:.6e}") for v in r] for r in H])
    )
    s = S.read_surface(f)  # the header's size and unit with it
    assert s.size == pytest.approx((4e-6, 8e-6), rel=1e-12)


@pytest.mark.parametrize(
    "edit, msg",
    [
        (
            lambda rows: rows[:2] + [rows[2].rsplit("\t", 1)[0]] + rows[3:],
            "line 6 holds 7 values where line 4 holds 8: every row of a height matrix",
        ),
        (
            lambda rows: rows[:1] + [rows[1] + "\t1e-8"] + rows[2:],
            "line 5 holds 9 values where line 4 holds 8",
        ),
        (
            lambda rows: rows[:3] + [rows[3].replace("e", "x", 1)] + rows[4:],
            "line 7, value 1: '.*x.*' is not a number",
        ),
    ],
)
def test_a_bad_row_is_named_by_the_files_line(tmp_path, edit, msg):
    rows = _rows("\t").splitlines()
    f = tmp_path / "m.txt"
    f.write_text(HEAD + "\n".join(edit(rows)) + "\n")
    with pytest.raises(ValueError, match=msg) as info:
        load_matrix(f, "m")
    assert "usecols" not in str(info.value) and str(info.value).startswith(str(f))


def test_semicolon_rows_with_a_thousands_point_or_an_empty_cell_are_named(tmp_path):
    f = tmp_path / "m.txt"
    f.write_text("1,5;2,5\n1.234,5;3,5\n")
    with pytest.raises(
        ValueError, match="line 2, value 1: '1.234,5' is not a number \\(a thousands separator"
    ):
        load_matrix(f, "m")
    f.write_text("1;2;\n3;4;\n")
    with pytest.raises(ValueError, match="line 1, value 3: '' is not a number \\(empty"):
        load_matrix(f, "m")
    f.write_text("1.5,2.5\n0,5 1,5\n")  # a comma file: 0,5 is no number there
    with pytest.raises(
        ValueError, match="line 2, value 2: '5 1' is not a number \\(a decimal comma in a comma-sep"
    ):
        load_matrix(f, "m")


def test_a_header_with_half_a_size_says_which_half_is_missing(tmp_path, capsys):
    f = tmp_path / "w.txt"
    f.write_text("# Width: 8.00 um\n# Value units: m\n" + _rows("\t"))
    with pytest.raises(S.SizeRequired, match="gives '# Width: 8.00 um' but no '# Height:' line"):
        S.read_raw(f)
    g = tmp_path / "h.txt"
    g.write_text("# Height: 4 um\n# Value units: m\n" + _rows("\t"))
    with pytest.raises(S.SizeRequired, match="gives '# Height: 4 um' but no '# Width:' line"):
        S.read_raw(g)
    h, dx, dy, _ = S.read_raw(f, size=(4e-6, 8e-6))  # the width agrees: read
    assert (dx, dy) == pytest.approx((1e-6, 1e-6), rel=1e-12)
    with pytest.raises(S.SizeContradiction, match="makes the width 4e-06 m where the file's"):
        S.read_raw(f, size=4e-6)
    h, dx, dy, prov = S.read_raw(f, override_size=(2e-6, 2e-6))  # the override replaces it
    assert (dx, dy) == pytest.approx((0.5e-6, 0.25e-6)) and prov["size_source"] == "override"
    argv = ["--workpiece", str(f), "--tool", str(f), "--out", str(tmp_path / "o")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "no '# Height:' line (the extent over the lines, axis 0); add it, or give --size" in err
    assert "does not say its size" not in err
