"""The selected marker's gaps are shaded in the Curves plot, on the pixels: CMU 01_01 with its
C3D, the band covers exactly the x range of the gap's frames."""

from __future__ import annotations

import numpy as np
import pytest
from PyQt6.QtWidgets import QApplication

from gmr_studio.app.docks.timeplot import SPAN_BRUSH
from gmr_studio.app.media.video import image_pixels
from gmr_studio.core.analysis.curves import gap_spans
from tests import app_fixtures
from tests.app_fixtures import open_file
from tests.conftest import shared_path
from tests.test_app_curves import pixel_of_frame

pytestmark = pytest.mark.gui
studio = app_fixtures.studio

BACKGROUND = (0x1E, 0x1F, 0x22)  # TimePlot's background colour


def test_the_longest_gap_of_a_marker_is_shaded_over_its_frames(studio):
    open_file(studio, shared_path("cmu/subject01/01_01.bvh"), shared_path("cmu/subject01/01_01.c3d"))
    studio.curves_dock.show()  # hidden in the default layout until asked for
    state, plot = studio.state, studio.curves.plot
    # the cameras' samples alone: the lab's gap filling (computed samples, kept when read)
    # leaves no lone gap of 5 frames
    state.set_markers(state.marker_overlay.markers.without_computed())
    overlay = state.marker_overlay
    # the longest gap of 5 frames or more with no other gap of its marker within a margin
    candidates = []
    for m in range(overlay.positions.shape[1]):
        gaps = gap_spans(overlay.positions[:, m])
        for a, b in gaps:
            margin = max(int(b - a), 20)
            alone = ((gaps[:, 0] < b + margin) & (gaps[:, 1] > a - margin)).sum() == 1
            if b - a >= 5 and alone and a - margin >= 0 and b + margin <= state.n_frames:
                candidates.append((int(b - a), m, int(a), int(b)))
    assert candidates, "01_01's C3D has no lone marker gap of 5 frames or more"
    _, marker, start, stop = max(candidates)
    margin = max(stop - start, 20)
    state.select(None)
    state.select_marker(marker)
    np.testing.assert_array_equal(plot.spans, gap_spans(overlay.positions[:, marker]))
    plot.plot_item.showGrid(x=False, y=False)
    plot.view_box.setXRange(start - margin, stop + margin, padding=0)
    state.set_frame(max(start - margin - 50, 0))  # the cursor out of view
    QApplication.processEvents()
    plot.legend.hide()  # its dark box would cover the columns measured here
    pixels = image_pixels(plot.plot_widget.viewport().grab().toImage()).astype(float)
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
