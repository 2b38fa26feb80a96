"""The drawables' base (app/scene/drawable.py, issue 24): named parts put into the scene's
main renderer or its front layer, replaced by name, taken out on removal and rebuilding,
and one visibility switch over them all that a part's own wish can narrow."""

from __future__ import annotations

import numpy as np
import pytest

from gmr_studio.app.scene import vtk_parts as parts
from gmr_studio.app.scene.drawable import Drawing
from tests.tiny_scene import figure_motion, holds, props_of, scene_of, snapshot_of

pytestmark = pytest.mark.gui


class Dots(Drawing):
    """A sphere at each joint (the part ``dots``), and a one-point part ``spare``."""

    def build(self, scene) -> None:
        super().build(scene)
        self.add("dots", parts.sphere_part(scene.snapshot.motion.n_joints, 0.01))
        self.add("spare", parts.sphere_part(1, 0.01))

    def show_frame(self, frame: int) -> None:
        self.parts["dots"].set_points(self.scene.snapshot.positions[frame])


class FrontDots(Dots):
    front = True


class OnlyDots(Dots):
    """Wants its ``dots`` shown, never its ``spare``."""

    def part_wanted(self, part) -> bool:
        return part is self.parts.get("dots")


def test_a_drawing_is_wanted_and_visible_until_told_otherwise():
    drawing = Drawing()
    assert drawing.visible is True and drawing.parts == {} and drawing.scene is None
    assert drawing.wanted(None) is True
    assert drawing.part_wanted(parts.Part(1)) is True
    drawing.remove()  # never built: nothing to take out, no scene asked
    assert drawing.parts == {}
    with pytest.raises(AssertionError, match="build the drawable"):
        drawing.add("dots", parts.sphere_part(1, 0.01))


def test_parts_go_into_the_main_renderer_and_are_shown():
    with scene_of(snapshot_of(figure_motion())) as scene:
        dots = Dots()
        scene.add_drawable(dots)
        main, front = scene.plotter.renderer, scene.front_renderer
        assert set(dots.parts) == {"dots", "spare"}
        for part in dots.parts.values():
            assert holds(main, part.actor) and not holds(front, part.actor)
            assert part.visible
        np.testing.assert_array_equal(dots.parts["dots"].mesh.points, scene.snapshot.positions[0])


def test_a_front_drawing_draws_in_the_front_layer_only():
    with scene_of(snapshot_of(figure_motion())) as scene:
        main_before = props_of(scene.plotter.renderer)
        dots = FrontDots()
        scene.add_drawable(dots)
        for part in dots.parts.values():
            assert holds(scene.front_renderer, part.actor) and part.visible
        assert props_of(scene.plotter.renderer) == main_before
        dots.remove()
        assert props_of(scene.front_renderer) == [] and dots.parts == {}


def test_a_part_added_under_a_taken_name_replaces_the_old_one():
    with scene_of(snapshot_of(figure_motion())) as scene:
        dots = Dots()
        scene.add_drawable(dots)
        renderer = scene.plotter.renderer
        old = dots.parts["spare"]
        new = dots.add("spare", parts.sphere_part(2, 0.02))
        assert dots.parts["spare"] is new and new.visible
        assert holds(renderer, new.actor) and not holds(renderer, old.actor)
        assert holds(renderer, dots.parts["dots"].actor)  # the other part stays


def test_rebuilding_and_removing_take_the_old_actors_out():
    with scene_of(snapshot_of(figure_motion())) as scene:
        renderer = scene.plotter.renderer
        before = props_of(renderer)
        dots = Dots()
        scene.add_drawable(dots)
        first = [part.actor for part in dots.parts.values()]
        scene.redraw(dots)
        assert not any(holds(renderer, actor) for actor in first)
        assert len(props_of(renderer)) == len(before) + 2
        scene.remove_drawable(dots)
        assert props_of(renderer) == before and dots.parts == {}


def test_one_switch_hides_and_shows_every_part():
    with scene_of(snapshot_of(figure_motion())) as scene:
        dots = Dots()
        scene.add_drawable(dots)
        dots.set_visible(False)
        assert dots.visible is False and not any(part.visible for part in dots.parts.values())
        dots.build(scene)  # built again while hidden: its new parts hidden too
        assert not any(part.visible for part in dots.parts.values())
        dots.set_visible(1)
        assert dots.visible is True and all(part.visible for part in dots.parts.values())


def test_a_part_not_wanted_stays_hidden_while_the_drawing_is_shown():
    with scene_of(snapshot_of(figure_motion())) as scene:
        dots = OnlyDots()
        scene.add_drawable(dots)
        assert dots.parts["dots"].visible and not dots.parts["spare"].visible
        dots.set_visible(True)
        assert dots.parts["dots"].visible and not dots.parts["spare"].visible
        dots.set_visible(False)
        assert not dots.parts["dots"].visible and not dots.parts["spare"].visible


def _drawable_classes() -> list[type]:
    """Every class the view draws with: :class:`Drawing` and its subclasses in app/scene."""
    import importlib

    for name in ("figure", "highlight", "problem_marks", "overlays", "ghost_layer", "onion", "layer_onion"):
        importlib.import_module(f"gmr_studio.app.scene.{name}")
    found, todo = [], [Drawing]
    while todo:
        cls = todo.pop()
        found.append(cls)
        todo.extend(cls.__subclasses__())
    return [cls for cls in found if cls.__module__.startswith("gmr_studio.app.scene.")]


def test_every_drawable_has_the_protocols_members_of_the_same_kind():
    """The scene reads ``visible`` as a value (``if drawable.visible:``): a drawable whose
    ``visible`` were a method would always count as shown. Each member is what the protocol
    declares it: a property, or a method."""
    from gmr_studio.app.scene.drawable import Drawable

    members = ("build", "show_frame", "wanted", "visible", "set_visible", "remove")
    declared = {name: isinstance(Drawable.__dict__[name], property) for name in members}
    assert declared == {name: name == "visible" for name in members}
    classes = _drawable_classes()
    assert len(classes) > 8, [cls.__name__ for cls in classes]
    for cls in classes:
        for name, is_property in declared.items():
            member = next(vars(c)[name] for c in cls.__mro__ if name in vars(c))
            assert isinstance(member, property) == is_property, f"{cls.__name__}.{name}"
            assert is_property or callable(member), f"{cls.__name__}.{name}"
