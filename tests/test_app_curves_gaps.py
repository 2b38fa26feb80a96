"""The selected marker's gaps are shaded in the Curves plot, on the pixels: CMU 01_01 with its
C3D, the band covers exactly the x range of the gap's frames."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.timeplot import SPAN_BRUSH
from gmr_studio.core.curves import gap_spans
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path
from tests.test_app_curves import image_array, pixel_of_frame

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

BACKGROUND = (0x1E, 0x1F, 0x22)  # TimePlot's background colour


def test_the_longest_gap_of_a_marker_is_shaded_over_its_frames(studio):
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"), shared_path("cmu/subject01/01_01.c3d"))
    state, plot = studio.state, studio.curves.plot
    overlay = state.marker_overlay
    spans = [gap_spans(overlay.positions[:, m]) for m in range(overlay.positions.shape[1])]
    lengths = [int((s[:, 1] - s[:, 0]).max()) if len(s) else 0 for s in spans]
    marker = int(np.argmax(lengths))
    gaps = spans[marker]
    start, stop = (int(v) for v in gaps[np.argmax(gaps[:, 1] - gaps[:, 0])])
    assert stop - start >= 5, "01_01's C3D has no marker gap of 5 frames or more"
    state.select(None)
    state.select_marker(marker)
    state.set_frame(0)
    margin = max(stop - start, 20)
    # the gap and a margin on each side in view, alone (no other gap there), no grid lines
    assert not any(a < stop + margin and b > start - margin for a, b in gaps if (a, b) != (start, stop))
    plot.plot_item.showGrid(x=False, y=False)
    plot.view_box.setXRange(start - margin, stop + margin, padding=0)
    state.set_frame(max(start - margin - 50, 0))  # the cursor out of view
    QApplication.processEvents()
    pixels = image_array(plot.plot_widget.viewport().grab().toImage()).astype(float)
    box = plot.plot_widget.mapFromScene(plot.view_box.sceneBoundingRect()).boundingRect()
    rows = pixels[box.top() + 2 : box.bottom() - 1, box.left() + 2 : box.right() - 1]
    column_colour = np.median(rows, axis=0)  # (W, 3): a column is background or band, with a curve across
    x_of = lambda frame: pixel_of_frame(plot, frame).x() - (box.left() + 2)  # noqa: E731
    red, green, blue, alpha = SPAN_BRUSH
    band = np.array(BACKGROUND) + (np.array((red, green, blue)) - BACKGROUND) * alpha / 255
    columns = np.arange(column_colour.shape[0])
    inside = (columns > x_of(start) + 1) & (columns < x_of(stop) - 1)
    outside = (columns < x_of(start) - 2) | (columns > x_of(stop) + 2)
    assert inside.sum() >= 20 and outside.sum() >= 20
    np.testing.assert_allclose(column_colour[inside], np.broadcast_to(band, (inside.sum(), 3)), atol=4)
    np.testing.assert_allclose(column_colour[outside], np.broadcast_to(BACKGROUND, (outside.sum(), 3)), atol=4)
