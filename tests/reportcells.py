"""Reading a report.html back: every number with its ``data-key`` (and ``data-scale``)."""

from html.parser import HTMLParser

import pytest


class Cells(HTMLParser):
    """``{data-key: value}`` of every element with a ``data-key`` (the text divided by its
    ``data-scale``: the value in the record's unit), the embedded images, remote links."""

    def __init__(self, text=None):
        super().__init__()
        self.cells, self.text, self._key, self._scale, self.images, self.remote = (
            {}, {}, None, 1.0, 0, [],
        )  # fmt: skip
        if text is not None:
            self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self._key = a.get("data-key")
        self._scale = float(a.get("data-scale") or 1.0)
        if tag == "img":
            self.images += a["src"].startswith("data:image/png;base64,")
        for k in ("src", "href"):
            if k in a and "://" in a[k]:
                self.remote.append(a[k])

    def handle_data(self, data):
        if self._key is not None:
            self.text[self._key] = data
            self.cells[self._key] = None if data == "-" else float(data) / self._scale
            self._key = None


def lookup(record, key):
    """The value at the dotted path ``key`` of a JSON record (list indices as numbers)."""
    v = record
    for part in key.split("."):
        v = v[int(part)] if isinstance(v, list) else v[part]
    return v


def _digits(text):
    """Significant digits of a number as printed (``0.0138`` -> 3, ``7.6e+08`` -> 2)."""
    mantissa = text.lower().split("e")[0].lstrip("+-").replace(".", "").lstrip("0")
    return max(1, len(mantissa))


def assert_page_agrees(page, record):
    """Every number of the page is the record's at its key, to the digits the page shows."""
    for key, value in page.cells.items():
        want = lookup(record, key)
        if value is None:
            assert want is None, key
        else:
            rel = 0.51 * 10.0 ** (1 - _digits(page.text[key]))
            assert value == pytest.approx(want, rel=rel, abs=1e-300), (key, page.text[key], want)
