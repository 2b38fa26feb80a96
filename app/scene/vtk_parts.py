"""Small VTK building blocks whose points are updated in place every frame.

Each part owns a :class:`pyvista.PolyData` with a fixed number of points and the actor that
draws it; :meth:`Part.set_points` writes new coordinates into the existing VTK array and
marks it modified, so a frame costs a copy of a few hundred floats and one render. No VTK
filter runs on a frame change: spheres and bones are drawn by the GPU as shaded imposters
(:func:`sphere_part`, :func:`bone_part`: one square or box each, the surface and depth
computed per pixel, so they cost the same at any size and are round at any zoom), cubes and
markers are templates that the mapper places (:func:`glyph_part`: instanced by
``vtkGlyph3DMapper``), a selection ring is a circle turned to the camera and moved by its
actor's position (:func:`ring_part`), and lines are drawn as they are. Labels, quads of one
texture at display pixels, are in :mod:`app.scene.labels`.
"""

from __future__ import annotations

import numpy as np
import pyvista as pv
import vtkmodules.vtkRenderingFreeType  # noqa: F401 (the text renderer's implementation)
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import (
    vtkActor,
    vtkCamera,
    vtkFollower,
    vtkGlyph3DMapper,
    vtkMapper,
    vtkPolyDataMapper,
    vtkProp,
    vtkTextProperty,
    vtkTextRenderer,
    vtkTexture,
)
from vtkmodules.vtkRenderingOpenGL2 import vtkOpenGLSphereMapper, vtkOpenGLStickMapper


def rgb_bytes(colors: np.ndarray) -> np.ndarray:
    """(N, 3) floats in [0, 1] -> (N, 3) uint8."""
    return np.clip(np.rint(np.asarray(colors, dtype=np.float64) * 255), 0, 255).astype(np.uint8)


def unshifted(actor) -> None:
    """Have ``actor``'s mapper send its points to OpenGL as they are, not shifted and scaled
    about their range. VTK's default shift and scale keep float32 precise for data far from
    the origin; to choose it VTK measures every point array whenever it changes, and that
    measure asks the C library for the processors online (open and read a file in /sys)
    twice per array: a frame's points change every frame, and this was a tenth of a
    millisecond of each render. Motion capture sits within a few thousand units of the
    origin, where float32 keeps ~1e-4 of a unit."""
    mapper = actor.GetMapper() if hasattr(actor, "GetMapper") else None
    if mapper is not None and hasattr(mapper, "SetVBOShiftScaleMethod"):
        mapper.SetVBOShiftScaleMethod(vtkPolyDataMapper.DISABLE_SHIFT_SCALE)


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
    part.actor = _coloured_actor(mapper, part.mesh, n_points, colors, color)
    return part


class SpherePart(Part):
    """Spheres of one radius (the scene's units) at ``n`` points; a point given as NaN is
    not drawn (its sphere's radius is set to 0), so missing markers and unflagged joints
    cost no new arrays: the points and radii are written in place every frame.

    Drawn by ``vtkOpenGLSphereMapper``: each sphere is one screen-facing square whose
    fragment shader computes the sphere's surface, normal and depth, so it is lit and hides
    what is behind it like a mesh sphere, with no triangles to transform: far cheaper than
    tessellated spheres, above all in software OpenGL.
    """

    def __init__(self, n_points: int, radius: float) -> None:
        super().__init__(n_points)
        self.radius = float(radius)
        self.mesh.verts = _vertex_cells(n_points)
        # the mapper reads the radii as 32-bit floats (a 64-bit array crashes its shader setup)
        self.mesh.point_data["radius"] = np.full(n_points, self.radius, dtype=np.float32)
        self._radii = self.mesh.point_data["radius"] if n_points else np.zeros(0, np.float32)
        #: (n,) float32: each point's sphere radius when drawn (:attr:`radius` unless
        #: :meth:`set_sizes` changed it)
        self.sizes = np.full(n_points, self.radius, dtype=np.float32)
        #: (n, 3) uint8: the per-point colours VTK draws, written in place (None: one colour)
        self.colors: np.ndarray | None = None

    def set_points(self, points: np.ndarray) -> None:
        """Write (n, 3) coordinates; rows with a NaN are not drawn."""
        if not self.n_points:
            return
        points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        present = np.isfinite(points).all(axis=1)
        self._view[:] = np.where(present[:, None], points, 0.0)
        self._radii[:] = np.where(present, self.sizes, 0.0)
        self.mesh.GetPoints().Modified()

    def set_sizes(self, indices: np.ndarray, radius: float) -> None:
        """Draw the spheres of points ``indices`` (K,) with ``radius`` from now on (those
        drawn now at once, those not drawn, a NaN's, left undrawn)."""
        if not self.n_points:
            return
        self.sizes[indices] = radius
        self._radii[indices] = np.where(self._radii[indices] > 0, np.float32(radius), np.float32(0.0))

    @property
    def drawn(self) -> np.ndarray:
        """(n,) bool: the points drawn now."""
        return np.asarray(self._radii) > 0


def _vertex_cells(n: int) -> np.ndarray:
    """The cell array of ``n`` vertex cells, one per point (what the imposter mappers draw)."""
    return np.column_stack([np.ones(n, dtype=np.int64), np.arange(n)]).ravel()


def sphere_part(n_points: int, radius: float, colors: np.ndarray | None = None, color=(1.0, 1.0, 1.0)) -> SpherePart:
    """Spheres of ``radius`` at ``n_points`` points, coloured per point (``colors`` (n, 3) in
    [0, 1]) or all one ``color``; update with :meth:`SpherePart.set_points`."""
    part = SpherePart(n_points, radius)
    mapper = vtkOpenGLSphereMapper()
    mapper.SetInputData(part.mesh)
    mapper.SetRadius(part.radius)
    mapper.SetScaleArray("radius")
    part.actor = _coloured_actor(mapper, part.mesh, n_points, colors, color)
    if colors is not None and n_points:
        part.colors = part.mesh.point_data["colors"]
    return part


def _coloured_actor(mapper: vtkMapper, mesh: pv.PolyData, n: int, colors, color) -> vtkActor:
    """The actor of a glyph or sphere mapper over ``mesh`` (``n`` points): one colour per glyph from
    ``colors`` (n, 3) in [0, 1] (a ``colors`` point array the mapper reads by name), or all
    one ``color``."""
    if colors is not None and n:
        mesh.point_data["colors"] = rgb_bytes(colors)
        mapper.SetScalarModeToUsePointFieldData()
        mapper.SelectColorArray("colors")
        mapper.SetColorModeToDirectScalars()
        mapper.ScalarVisibilityOn()
    else:
        mapper.ScalarVisibilityOff()
    actor = _surface_actor(mapper)
    if colors is None:
        actor.GetProperty().SetColor(*color)
    return actor


RING_SEGMENTS = 48  # a circle of 48 chords: round to 1/300 of its radius


class RingPart(Part):
    """A circle of ``radius`` (the scene's units) around one point, turned to the camera at
    every render (``vtkFollower``): a selection ring. The mesh holds the one point (the
    centre, written in place as every part's); the actor draws a closed line of
    :data:`RING_SEGMENTS` chords in its own x-y plane, moved by its position, so following
    the point costs no upload and no filter (a wireframe sphere of the same size would draw
    thousands of line segments every frame)."""

    def __init__(self, radius: float, camera: vtkCamera, color, width: float) -> None:
        super().__init__(1)
        self.radius = float(radius)
        angles = np.linspace(0.0, 2.0 * np.pi, RING_SEGMENTS, endpoint=False)
        self.circle = pv.PolyData(self.radius * np.column_stack([np.cos(angles), np.sin(angles), 0.0 * angles]))
        self.circle.lines = np.concatenate([[RING_SEGMENTS + 1], np.arange(RING_SEGMENTS), [0]])
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(self.circle)
        mapper.ScalarVisibilityOff()
        self.actor = vtkFollower()
        self.actor.SetMapper(mapper)
        self.actor.SetCamera(camera)
        prop = self.actor.GetProperty()
        prop.SetAmbient(1.0)
        prop.SetDiffuse(0.0)
        prop.SetSpecular(0.0)
        prop.SetColor(*color)
        prop.SetLineWidth(width)

    def set_points(self, points: np.ndarray) -> None:
        """Centre the ring on ``points`` (1, 3) (NaN read as 0: hide the ring for a gap)."""
        super().set_points(points)
        self.actor.SetPosition(*self._view[0])


def ring_part(radius: float, camera: vtkCamera, color=(1.0, 1.0, 1.0), width: float = 2.5) -> RingPart:
    """A selection ring of ``radius`` facing ``camera`` (the renderer's active camera), ``width``
    pixels wide; place it with :meth:`RingPart.set_points`."""
    return RingPart(radius, camera, color, width)


def segments_part(
    n_points: int,
    pairs: np.ndarray,
    colors: np.ndarray | None = None,
    color=(1.0, 1.0, 1.0),
    *,
    width: float = 2.0,
    opacity: float = 1.0,
) -> Part:
    """Line segments between point pairs ((S, 2) indices), one colour per segment
    (``colors`` (S, 3)) or one ``color``, ``width`` pixels wide (bones with a thickness in
    the scene's units: :func:`bone_part`)."""
    part = Part(n_points)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    if n_points and len(pairs):
        part.mesh.lines = np.column_stack([np.full(len(pairs), 2), pairs]).ravel()
    if colors is not None and len(pairs):
        part.mesh.cell_data["colors"] = rgb_bytes(colors)
        part.mesh.cell_data.active_scalars_name = "colors"
    mapper = vtkPolyDataMapper()
    mapper.SetInputData(part.mesh)
    if colors is not None and len(pairs):
        mapper.SetScalarModeToUseCellData()
        mapper.SetColorModeToDirectScalars()
        mapper.ScalarVisibilityOn()
    else:
        mapper.ScalarVisibilityOff()
    part.actor = _surface_actor(mapper, ambient=1.0, diffuse=0.0)
    part.actor.GetProperty().SetLineWidth(width)
    part.actor.GetProperty().SetOpacity(opacity)
    if colors is None:
        part.actor.GetProperty().SetColor(*color)
    return part


class BonePart(Part):
    """Bones between point pairs as cylinders of a fixed radius (the scene's units), drawn by
    the GPU as imposters (``vtkOpenGLStickMapper``: one screen-facing box a bone, the
    cylinder's surface and depth computed per pixel), as spheres are (:class:`SpherePart`).

    The points of the mesh are the bones' midpoints (B,); :meth:`set_joints` computes them,
    the directions and the lengths from the joints' positions, in place. The mapper reads a
    unit ``direction`` and a ``scale`` of (length, radius, radius) per bone, as 32-bit
    floats, and a colour per bone (it has no single-colour mode: one ``color`` is repeated).
    """

    def __init__(self, pairs: np.ndarray, radius: float, colors: np.ndarray | None, color) -> None:
        self.pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
        super().__init__(len(self.pairs))
        n = len(self.pairs)
        self.radius = float(radius)
        if n:  # pyvista refuses empty arrays; a one-joint figure has no bones
            self.mesh.verts = _vertex_cells(n)
            self.mesh.point_data["direction"] = np.tile(np.float32([1.0, 0.0, 0.0]), (n, 1))
            self.mesh.point_data["scale"] = np.zeros((n, 3), dtype=np.float32)
            self._direction = self.mesh.point_data["direction"]
            self._scale = self.mesh.point_data["scale"]
            self._scale[:, 1:] = self.radius
        mapper = vtkOpenGLStickMapper()
        mapper.SetInputData(self.mesh)
        mapper.SetOrientationArray("direction")
        mapper.SetScaleArray("scale")
        rgb = colors if colors is not None else np.broadcast_to(np.asarray(color, dtype=np.float64), (n, 3))
        self.actor = _coloured_actor(mapper, self.mesh, n, rgb, color)

    def set_joints(self, joints: np.ndarray) -> None:
        """Place every bone between its two joints: ``joints`` (J, 3), NaN-free."""
        if not len(self.pairs):
            return
        a, b = joints[self.pairs[:, 0]], joints[self.pairs[:, 1]]
        along = b - a
        length = np.sqrt(np.einsum("ij,ij->i", along, along))
        self._view[:] = 0.5 * (a + b)
        self._direction[:] = along / np.where(length > 0, length, 1.0)[:, None]
        self._scale[:, 0] = length
        self.mesh.GetPoints().Modified()
        self.mesh.GetPointData().Modified()


def bone_part(pairs: np.ndarray, radius: float, colors: np.ndarray | None = None, color=(1.0, 1.0, 1.0)) -> BonePart:
    """Bones between joint pairs ((B, 2) indices), one colour per bone (``colors`` (B, 3)) or
    one ``color``; update with :meth:`BonePart.set_joints`."""
    return BonePart(pairs, radius, colors, color)


def rgba_texture(image: np.ndarray) -> vtkTexture:
    """A texture of ``image`` (H, W, 4) uint8 RGBA, rows bottom first (VTK's order), drawn
    one texel a pixel (not interpolated: text stays sharp)."""
    height, width = image.shape[:2]
    texels = vtkImageData()
    texels.SetDimensions(width, height, 1)
    texels.GetPointData().SetScalars(numpy_to_vtk(image.reshape(-1, 4), deep=True))
    texture = vtkTexture()
    texture.SetInputData(texels)
    texture.InterpolateOff()
    return texture


def render_texts(texts: list[str], color, size: int) -> tuple[list[np.ndarray], list[tuple[int, int]]]:
    """Each text as an (h, w, 4) RGBA image (VTK's rows: bottom first) and its (w, h)."""
    renderer = vtkTextRenderer()
    prop = vtkTextProperty()
    prop.SetFontSize(size)
    prop.SetColor(*color)
    prop.SetBold(False)
    prop.SetShadow(True)
    tiles, dims = [], []
    for text in texts:
        if not text:
            tiles.append(np.zeros((1, 1, 4), np.uint8))
            dims.append((1, 1))
            continue
        image, extent = vtkImageData(), [0, 0]
        renderer.RenderString(prop, text, image, extent, 72)
        w_img, h_img, _ = image.GetDimensions()
        pixels = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h_img, w_img, -1)
        w, h = max(int(extent[0]), 1), max(int(extent[1]), 1)
        tiles.append(np.ascontiguousarray(pixels[:h, :w, :4]))
        dims.append((w, h))
    return tiles, dims


def draws_anything(renderer) -> bool:
    """Whether ``renderer`` has a visible prop with something to draw (a mapper's input with
    points, or a prop without a mapper). The scene leaves an empty layer undrawn: a second
    layer costs a pass over the whole view."""
    props = renderer.GetViewProps()
    for index in range(props.GetNumberOfItems()):
        prop = props.GetItemAsObject(index)
        if not prop.GetVisibility():
            continue
        mapper = prop.GetMapper() if hasattr(prop, "GetMapper") else None
        data = mapper.GetInputDataObject(0, 0) if mapper is not None else None
        if data is None or not hasattr(data, "GetNumberOfPoints") or data.GetNumberOfPoints() > 0:
            return True
    return False
