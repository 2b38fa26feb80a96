"""Small VTK building blocks whose points are updated in place every frame.

Each part owns a :class:`pyvista.PolyData` with a fixed number of points and the actor that
draws it; :meth:`Part.set_points` writes new coordinates into the existing VTK array and
marks it modified, so a frame costs a copy of a few hundred floats and one render.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv
from vtkmodules.vtkFiltersCore import vtkTubeFilter
from vtkmodules.vtkRenderingCore import vtkActor, vtkActor2D, vtkGlyph3DMapper, vtkPolyDataMapper, vtkProp
from vtkmodules.vtkRenderingLabel import vtkLabeledDataMapper


def rgb_bytes(colors: np.ndarray) -> np.ndarray:
    """(N, 3) floats in [0, 1] -> (N, 3) uint8."""
    return np.clip(np.rint(np.asarray(colors, dtype=np.float64) * 255), 0, 255).astype(np.uint8)


class Part:
    """A poly data with ``n`` points, drawn by ``actor``; coordinates updated in place."""

    def __init__(self, n_points: int) -> None:
        self.mesh = pv.PolyData()  # points only: no vertex cells, so cells are just the lines
        if n_points:
            self.mesh.points = np.zeros((n_points, 3))
        self._view = self.mesh.points if n_points else np.zeros((0, 3))
        self.actor: vtkProp | None = None

    @property
    def n_points(self) -> int:
        return len(self._view)

    def set_points(self, points: np.ndarray) -> None:
        """Write (n, 3) coordinates (NaN replaced by 0: mask or hide such points)."""
        if not self.n_points:
            return
        self._view[:] = np.nan_to_num(points, nan=0.0)
        self.mesh.GetPoints().Modified()

    def set_visible(self, visible: bool) -> None:
        if self.actor is not None:
            self.actor.SetVisibility(bool(visible))

    @property
    def visible(self) -> bool:
        return bool(self.actor is not None and self.actor.GetVisibility())


def _surface_actor(mapper, *, ambient: float = 0.35, diffuse: float = 0.65, opacity: float = 1.0) -> vtkActor:
    actor = vtkActor()
    actor.SetMapper(mapper)
    prop = actor.GetProperty()
    prop.SetAmbient(ambient)
    prop.SetDiffuse(diffuse)
    prop.SetSpecular(0.0)
    prop.SetOpacity(opacity)
    return actor


def glyph_part(n_points: int, source: pv.PolyData, colors: np.ndarray | None = None, color=(1.0, 1.0, 1.0)) -> Part:
    """A glyph (``source``, already at its drawn size) at each point, coloured per point
    (``colors`` (n, 3) in [0, 1]) or all one ``color``."""
    part = Part(n_points)
    mapper = vtkGlyph3DMapper()
    mapper.SetInputData(part.mesh)
    mapper.SetSourceData(source)
    mapper.SetScaling(False)
    mapper.OrientOff()
    if colors is not None and n_points:
        part.mesh.point_data["colors"] = rgb_bytes(colors)
        part.mesh.point_data.active_scalars_name = "colors"
        mapper.SetColorModeToDirectScalars()
        mapper.ScalarVisibilityOn()
    else:
        mapper.ScalarVisibilityOff()
    part.actor = _surface_actor(mapper)
    if colors is None:
        part.actor.GetProperty().SetColor(*color)
    return part


def set_some_points(part: Part, points: np.ndarray) -> None:
    """Give a single-colour glyph part a new set of points (any number; rows with NaN are
    left out, so gaps are simply not drawn). VTK's glyph masking does not notice changed
    masks, so the point set itself is replaced."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    kept = points[np.isfinite(points).all(axis=1)]
    part.mesh.points = kept if len(kept) else np.zeros((0, 3))
    part._view = part.mesh.points if len(kept) else np.zeros((0, 3))


def segments_part(
    n_points: int,
    pairs: np.ndarray,
    colors: np.ndarray | None = None,
    color=(1.0, 1.0, 1.0),
    *,
    width: float = 2.0,
    opacity: float = 1.0,
    tube_radius: float | None = None,
) -> Part:
    """Line segments between point pairs ((S, 2) indices), one colour per segment
    (``colors`` (S, 3)) or one ``color``; as tubes of ``tube_radius`` when given."""
    part = Part(n_points)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    if n_points and len(pairs):
        part.mesh.lines = np.column_stack([np.full(len(pairs), 2), pairs]).ravel()
    if colors is not None and len(pairs):
        part.mesh.cell_data["colors"] = rgb_bytes(colors)
        part.mesh.cell_data.active_scalars_name = "colors"
    mapper = vtkPolyDataMapper()
    if tube_radius is not None and len(pairs):
        tubes = vtkTubeFilter()
        tubes.SetInputData(part.mesh)
        tubes.SetRadius(tube_radius)
        tubes.SetNumberOfSides(12)
        tubes.CappingOn()
        mapper.SetInputConnection(tubes.GetOutputPort())
    else:
        mapper.SetInputData(part.mesh)
    if colors is not None and len(pairs):
        mapper.SetScalarModeToUseCellData()
        mapper.SetColorModeToDirectScalars()
        mapper.ScalarVisibilityOn()
    else:
        mapper.ScalarVisibilityOff()
    part.actor = _surface_actor(mapper, ambient=0.35 if tube_radius else 1.0, diffuse=0.65 if tube_radius else 0.0)
    part.actor.GetProperty().SetLineWidth(width)
    part.actor.GetProperty().SetOpacity(opacity)
    if colors is None:
        part.actor.GetProperty().SetColor(*color)
    return part


def label_part(n_points: int, texts: list[str], color=(1.0, 1.0, 1.0), size: int = 13) -> Part:
    """A text label at each point (the label follows the point)."""
    part = Part(n_points)
    mapper = vtkLabeledDataMapper()
    if n_points:
        array = pv.convert_array(np.array(texts, dtype=str), name="label")
        part.mesh.GetPointData().AddArray(array)
        mapper.SetInputData(part.mesh)
        mapper.SetLabelModeToLabelFieldData()
        mapper.SetFieldDataName("label")
    text = mapper.GetLabelTextProperty()
    text.SetColor(*color)
    text.SetFontSize(size)
    text.SetBold(False)
    text.SetShadow(True)
    text.SetJustificationToLeft()
    text.SetVerticalJustificationToBottom()
    actor = vtkActor2D()
    actor.SetMapper(mapper)
    part.actor = actor
    return part


def set_labels(part: Part, texts: list[str]) -> None:
    """Replace the label texts (same number of points)."""
    if part.n_points:
        array = pv.convert_array(np.array(texts, dtype=str), name="label")
        part.mesh.GetPointData().RemoveArray("label")
        part.mesh.GetPointData().AddArray(array)
        part.mesh.Modified()
