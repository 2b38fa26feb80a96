"""Mutation score per module, with cosmic-ray (docs/reliability.md, "Mutation testing").

cosmic-ray plants one small change at a time (an operator, a comparison, a number, a
condition negated...) in a module *on disk*, runs the tests chosen for that module, and
puts the file back. The project is installed editable (``gmr_studio.core`` is the
checkout's ``core/``), so the tests import the mutated file. A mutant the tests do not fail
is a survivor: a blind spot, unless it is *equivalent* (no input can tell it from the code),
which ``tests/mutation_equivalents.toml`` says with the reason.

    nice .venv/bin/python -m tests.mutation_score run core/clip.py [MODULE ...]   # minutes each
    GMR_REQUIRE_GUI=1 nice xvfb-run -a .venv/bin/python -m tests.mutation_score run app/reliability/autosave.py
    .venv/bin/python -m tests.mutation_score                     # the table, from the sessions kept
    .venv/bin/python -m tests.mutation_score survivors MODULE    # each non-equivalent survivor's diff
    nice .venv/bin/python -m tests.mutation_score rerun MODULE   # the survivors again, after new tests

Sessions are kept in ``.mutation/`` (not committed); ``run`` starts a module afresh. Not part
of the test suite and not run in CI (it edits the working tree while it runs: run it on a
tree nothing else is reading, one module at a time).

The operators are cosmic-ray's, reduced to a selective set (:data:`EXCLUDE`) so that a
module takes minutes, not hours, on 2 cores: each arithmetic operator is replaced by its
counterpart only (``+``/``-``, ``*``/``/``, ``|``/``&``...), not by all eleven others (which
on float arrays mostly raise TypeError, trivially killed); each comparison by its boundary
and its negation (``<`` by ``<=`` and ``>=``); unary operators only removed. Numbers,
booleans, ``not`` added, ``and``/``or``, ``break``/``continue``, exceptions and
zero-iteration loops are all kept.
"""

from __future__ import annotations

import json
import os
import shlex
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SESSIONS = ROOT / ".mutation"
EQUIVALENTS = ROOT / "tests" / "mutation_equivalents.toml"
#: goal: at most this fraction of the non-equivalent mutants survive, per module
GOAL = 0.10

#: module -> (tests that must catch its mutants, seconds before a mutant's run counts as a hang)
MODULES: dict[str, tuple[list[str], float]] = {
    "core/clip.py": (["tests/test_clip_edges.py", "tests/test_clip.py"], 60),
    "core/contacts.py": (["tests/test_contacts.py", "tests/test_mirror_contacts.py"], 60),
    "core/formats/amass.py": (["tests/test_amass.py"], 60),
    "core/formats/gltf.py": (
        [
            "tests/test_gltf_edges.py",
            "tests/test_gltf_units.py",
            "tests/test_gltf_fields.py",
            "tests/test_gltf_continuity.py",
            "tests/test_gltf.py",
        ],
        120,
    ),
    "app/model/joint_transforms.py": (["tests/test_joint_transforms.py"], 60),
    "core/table.py": (["tests/test_table_records.py", "tests/test_curves_cli.py", "tests/test_compare_cli.py"], 60),
    # the glTF reader (issue 25): its synthetic files (two seconds; the real ones take ten more)
    "core/formats/gltf_in/sampling.py": (["tests/test_gltf_sampling_mutants.py", "tests/test_gltf_read.py"], 60),
    "core/formats/gltf_in/pose.py": (["tests/test_gltf_pose_mutants.py", "tests/test_gltf_read.py"], 60),
    # the reader's own files first; tests/test_gltf.py reads back what the writer exports (pre-rotation too)
    "core/formats/gltf_in/rest.py": (
        ["tests/test_gltf_rest_mutants.py", "tests/test_gltf_read.py", "tests/test_gltf.py"],
        60,
    ),
    "core/formats/gltf_in/scene.py": (["tests/test_gltf_scene_mutants.py", "tests/test_gltf_read.py"], 60),
    "core/formats/gltf_in/reader.py": (["tests/test_gltf_reader_mutants.py", "tests/test_gltf_read.py"], 60),
    "core/formats/gltf_in/container.py": (["tests/test_gltf_container_mutants.py", "tests/test_gltf_read.py"], 60),
    "core/formats/gltf_in/contents.py": (["tests/test_gltf_contents_mutants.py", "tests/test_gltf_read.py"], 60),
    "core/channels.py": (
        [
            "tests/test_channels.py",
            "tests/test_joint_transforms.py",
            "tests/test_curves.py",
            "tests/test_curves_mirror_blind_spots.py",
        ],
        60,
    ),
    "core/curves.py": (
        [
            "tests/test_curves_edges.py",
            "tests/test_curves.py",
            "tests/test_curves_quantities.py",
            "tests/test_curves_mirror_blind_spots.py",
            "tests/test_curves_cli.py",
            "tests/test_joint_transforms.py",
        ],
        60,
    ),
    "core/mirror.py": (
        [
            "tests/test_mirror_edges.py",
            "tests/test_mirror_contacts.py",
            "tests/test_mirror_skeleton.py",
            "tests/test_curves_mirror_blind_spots.py",
        ],
        60,
    ),
    "core/compare/result.py": (
        [
            "tests/test_compare_result_edges.py",
            "tests/test_compare_blind_spots.py",
            "tests/test_compare.py",
            "tests/test_compare_cli.py",
        ],
        60,
    ),
    "core/compare/align.py": (
        [
            "tests/test_compare_align_edges.py",
            "tests/test_compare.py",
            "tests/test_compare_blind_spots.py",
            "tests/test_compare_cli.py",
        ],
        60,
    ),
    # the recovery tests but the one that runs the app in a subprocess (a minute a mutant)
    "app/reliability/autosave.py": (
        ["tests/test_app_autosave_rules.py", "tests/test_app_recovery.py", "-k", "not killed_app"],
        120,
    ),
    # the module has no widgets: its headless tests (the windows' tests cost half a minute a mutant)
    "app/reliability/recovery.py": (
        ["tests/test_recovery_records.py", "tests/test_recovery_liveness.py", "tests/test_app_autosave_rules.py"],
        120,
    ),
    # the audit's own tests run every shared file through every path (ten seconds): the quick ones first
    "core/compare/audit.py": (
        ["tests/test_audit_mutants.py", "tests/test_compare_blind_spots.py", "tests/test_audit.py"],
        120,
    ),
    "core/checks/spikes.py": (["tests/test_spikes_mutants.py", "tests/test_checks.py"], 60),
    "core/checks/feet.py": (["tests/test_feet_mutants.py", "tests/test_checks.py"], 60),
    "core/checks/joints.py": (["tests/test_joints_mutants.py", "tests/test_checks.py"], 60),
    "core/checks/frames.py": (["tests/test_frames_mutants.py", "tests/test_checks.py"], 60),
    "core/checks/model.py": (["tests/test_check_model_mutants.py", "tests/test_checks.py"], 60),
    "core/checks/report.py": (["tests/test_check_report_mutants.py", "tests/test_check_cli.py"], 60),
    "core/checks/context.py": (["tests/test_check_context_mutants.py", "tests/test_checks.py"], 60),
    # the pictures of docs/checks.md: their one test file (matplotlib, a real take)
    "core/checks/figures.py": (["tests/test_check_figures_mutants.py"], 60),
    # the raw markers' checks: small synthetic sets first, then the demo's markers and one small real C3D
    "core/checks/markers.py": (["tests/test_checks_markers_mutants.py", "tests/test_checks_markers.py"], 60),
    "core/checks/run.py": (["tests/test_check_run_mutants.py", "tests/test_checks.py"], 60),
    # the checks' model without a window (the windows' tests, tests/test_app_problems.py, take
    # half a minute a mutant)
    "app/model/problems.py": (["tests/test_problems_model_mutants.py"], 60),
    # the Problems dock on its own (a state, its problems, the dock; no window)
    "app/docks/problems_dock.py": (["tests/test_problems_dock_mutants.py"], 60),
    # the window's wiring: a window each test (half a second), small synthetic documents
    "app/window/comparison.py": (["tests/test_window_comparison_mutants.py"], 120),
    "app/window/checks.py": (["tests/test_window_checks_mutants.py"], 120),
    "core/compare/offset.py": (
        ["tests/test_offset_mutants.py", "tests/test_compare_offset.py", "tests/test_compare.py"],
        60,
    ),
    "core/compare/clock.py": (
        [
            "tests/test_clock_mutants.py",
            "tests/test_compare_slerp_reference.py",
            "tests/test_compare_offset.py",
            "tests/test_compare.py",
        ],
        60,
    ),
    # the engine against its sample-by-sample reference first (two seconds), then the compare
    # tests that drive it on the demo walk and the CMU take
    "core/compare/engine.py": (
        [
            "tests/test_engine_mutants.py",
            "tests/test_compare_slerp_reference.py",
            "tests/test_compare_blind_spots.py",
            "tests/test_compare.py",
        ],
        60,
    ),
    "core/compare/tracks.py": (
        ["tests/test_tracks_mutants.py", "tests/test_engine_mutants.py", "tests/test_compare.py"],
        60,
    ),
    # the layers' model without a window (the windows' tests compare the real CMU take: a
    # minute a mutant)
    "app/model/layers.py": (["tests/test_layers_mutants.py", "tests/test_app_layers_clock.py"], 120),
    # the marker file readers (issue 24): synthetic files written by the tests, and the few small real TRCs
    "core/markers/trc.py": (["tests/test_markers_trc_mutants.py", "tests/test_markers_trc.py"], 60),
    # the reader's rules on decoded arrays and stand-in child processes, then the few file tests
    # on files written by ezc3d or one small real file (the real files' own tests take a minute)
    "core/markers/c3d.py": (
        [
            "tests/test_markers_c3d_mutants.py",
            "tests/test_markers_c3d.py::test_written_file_with_residual_codes",
            "tests/test_markers_c3d.py::test_one_frame_file_and_metres",
            "tests/test_markers_c3d.py::test_broken_files_are_errors_not_crashes",
            "tests/test_markers_c3d.py::test_the_child_process_contract",
            "tests/test_markers_c3d.py::test_missing_file_and_truncated_data",
            "tests/test_markers_c3d.py::test_ezc3ds_requests_to_report_a_missing_feature_become_advice",
        ],
        60,
    ),
    # the SGI rewrite on small files built byte by byte, then the real SGI sample (43 kB)
    "core/markers/c3d_byteorder.py": (
        [
            "tests/test_markers_c3d_byteorder_mutants.py",
            "tests/test_markers_c3d.py::test_the_intel_copy_of_an_sgi_file_swaps_numbers_never_text",
            "tests/test_markers_c3d.py::test_a_damaged_sgi_file_gives_our_message",
        ],
        60,
    ),
    "core/markers/c3d_frames.py": (
        [
            "tests/test_markers_c3d_frames_mutants.py",
            "tests/test_markers_c3d.py::test_evart_points_follow_the_headers_layout",
        ],
        60,
    ),
    # the worker's functions in this process (ezc3d's reading stood in for), two worker processes,
    # and three isolated reads that run it as the child
    "core/markers/c3d_worker.py": (
        [
            "tests/test_markers_c3d_worker_mutants.py",
            "tests/test_markers_c3d.py::test_written_file_with_residual_codes",
            "tests/test_markers_c3d.py::test_a_damaged_sgi_file_gives_our_message",
            "tests/test_markers_c3d.py::test_evart_points_follow_the_headers_layout",
        ],
        60,
    ),
    "core/markers/file_model.py": (
        ["tests/test_markers_file_model_mutants.py", "tests/test_markers_sets.py::test_file_model_comparison_exact"],
        60,
    ),
    # the fit's edges on small synthetic arrays, then the root's translation on noisy CMU joints
    # (60 frames of a small AMC: a second) and the command line on one small real C3D
    "core/markers/root_fit.py": (["tests/test_markers_root_fit_mutants.py", "tests/test_markers_root_fit.py"], 60),
    # read_markers: the suffix's reader, its options, the refusal (a TRC written by the tests)
    "core/markers/__init__.py": (["tests/test_markers_read_markers_mutants.py"], 60),
    # the marker sets and skeleton building (issue 24): synthetic markers, core tests only
    "core/markers/match.py": (["tests/test_markers_match_mutants.py", "tests/test_markers_math.py"], 60),
    "core/markers/targets.py": (["tests/test_markers_targets.py"], 60),
    "core/markers/joint_names.py": (["tests/test_markers_joint_names.py"], 60),
    "core/markers/sets.py": (["tests/test_markers_set_files.py"], 60),
    "core/markers/markermap.py": (
        ["tests/test_markers_markermap.py", "tests/test_markers_map.py", "-k", "not pelvis_only_maps"],
        60,
    ),
    "core/markers/virtual.py": (
        ["tests/test_markers_virtual.py", "tests/test_markers_map.py", "-k", "not pelvis_only_maps"],
        60,
    ),
    "core/markers/built_motion.py": (["tests/test_markers_built_motion.py", "tests/test_markers_build.py"], 60),
    "core/markers/report.py": (["tests/test_markers_report.py"], 60),
    "core/markers/build.py": (
        ["tests/test_markers_build_mutants.py", "tests/test_markers_build.py", "tests/test_markers_built_motion.py"],
        60,
    ),
    # the marker set, then the TRC reader's and the maps' synthetic tests (the maps' real files cost four seconds)
    "core/markers/markerset.py": (
        [
            "tests/test_markers_markerset.py",
            "tests/test_markers_trc.py",
            "tests/test_markers_map.py",
            "-k",
            "not pelvis_only_maps",
        ],
        60,
    ),
    # the marker fits (issue 24): synthetic markers from a known skeleton
    "core/markers/procrustes.py": (["tests/test_procrustes_mutants.py", "tests/test_markers_math.py"], 60),
    "core/markers/limbs.py": (
        ["tests/test_limbs_mutants.py", "tests/test_markers_math.py", "tests/test_markers_build.py"],
        60,
    ),
    "core/markers/joint_centres.py": (["tests/test_joint_centres_mutants.py", "tests/test_markers_build.py"], 60),
    # the pelvis: synthetic clusters and triples first, then the real CMU markers
    "core/markers/pelvis.py": (
        [
            "tests/test_pelvis_mutants.py",
            "tests/test_markers_math.py",
            "tests/test_markers_solve.py::test_recover_pelvis_on_joint_markers_is_the_root_rotation",
            "tests/test_markers_pelvis_fit.py",
            "tests/test_markers_solve.py::test_real_cmu_markers_against_the_amc",
            "tests/test_markers_jointmap.py::test_recover_pelvis_on_the_bvh_and_a_skeleton_no_map_pairs",
        ],
        60,
    ),
    "core/markers/pelvis_guess.py": (["tests/test_pelvis_guess_mutants.py", "tests/test_markers_pelvis_guess.py"], 60),
    "core/markers/functional_joints.py": (
        ["tests/test_functional_joints_mutants.py", "tests/test_markers_knee_axis.py", "tests/test_markers_build.py"],
        60,
    ),
    # the refinement: the builder's generated sets (exact case, a perturbed pose) and the solver's exact case
    "core/markers/refine.py": (
        [
            "tests/test_refine_mutants.py",
            "tests/test_markers_build.py",
            "tests/test_markers_solve.py::test_refinement_keeps_the_exact_case",
        ],
        60,
    ),
    # the solver: the root fit's exact cases first (a tenth of a second each), then the solver's own
    # tests (generated skeletons, one CMU subject's short takes; six seconds in all)
    "core/markers/solve.py": (
        ["tests/test_markers_solve_mutants.py", "tests/test_markers_root_fit.py", "tests/test_markers_solve.py"],
        60,
    ),
    # the view's drawables (issue 24): a tiny synthetic figure in an off-screen scene (no window)
    "app/scene/drawable.py": (["tests/test_scene_drawable_mutants.py"], 60),
    "app/scene/figure.py": (["tests/test_scene_figure_mutants.py", "tests/test_scene_drawable_mutants.py"], 60),
    "app/scene/highlight.py": (["tests/test_scene_highlight_mutants.py"], 60),
    "app/scene/problem_marks.py": (["tests/test_scene_problem_marks_mutants.py"], 60),
    "app/scene/ghost_layer.py": (["tests/test_scene_ghost_layer_mutants.py"], 60),
    # the view's GPU parts: small parts drawn off screen (their arrays, actors and pixels), then
    # the imposters' first picture tests (a second in all: no window, no real file)
    "app/scene/vtk_parts.py": (
        [
            "tests/test_vtk_parts_arrays.py",
            "tests/test_vtk_parts_pictures.py",
            "tests/test_app_drawables.py::test_imposter_spheres_cover_their_disc_and_a_missing_point_draws_nothing",
            "tests/test_app_drawables.py::test_imposter_bones_run_from_joint_to_joint",
        ],
        60,
    ),
    # the view's overlays (issue 24): a stand-in scene with a bare renderer, a tiny synthetic motion
    "app/scene/overlays.py": (["tests/test_app_overlays_mutants.py"], 60),
    # the dock policy: plain widgets and tabbed docks of a small main window (the app's docks'
    # own tests open the real window on a real take: seconds a mutant)
    "app/docks/frame_follow.py": (["tests/test_app_frame_follow_mutants.py"], 60),
    # the layout's rules on a small main window of plain widgets (the real window's layout tests
    # open a real take at two sizes: ten seconds a mutant)
    "app/window/layout.py": (["tests/test_app_layout_mutants.py"], 60),
    # the view's widget kind: environments given as dicts, the process-wide choice reset per test
    "app/scene/render_widget.py": (["tests/test_app_render_widget_mutants.py"], 60),
    # the classroom's drawing: a tiny synthetic motion, a stand-in scene with bare renderers
    "app/scene/teach_overlay.py": (["tests/test_app_teach_overlay_mutants.py"], 60),
    # the scene itself: its list of drawables, the camera, the projection and the onion skins,
    # on the tiny figure (no window)
    "app/scene/scene.py": (
        [
            "tests/test_scene_scene_mutants.py",
            "tests/test_scene_render_mutants.py",
            "tests/test_scene_drawable_mutants.py",
            "tests/test_scene_figure_mutants.py",
            "tests/test_scene_highlight_mutants.py",
        ],
        60,
    ),
    "app/scene/camera.py": (["tests/test_scene_camera_mutants.py", "tests/test_scene_scene_mutants.py"], 60),
    "app/scene/picking.py": (
        ["tests/test_scene_picking_mutants.py", "tests/test_app_picking.py", "tests/test_scene_camera_mutants.py"],
        60,
    ),
    "app/scene/onion.py": (["tests/test_scene_onion_mutants.py", "tests/test_scene_layer_onion_mutants.py"], 60),
    "app/scene/layer_onion.py": (["tests/test_scene_layer_onion_mutants.py"], 60),
}
#: operators left out (regular expressions, matched from the start of cosmic-ray's names)
EXCLUDE = [
    r"core/ReplaceBinaryOperator_(?!(Add_Sub|Sub_Add|Mul_Div|Div_Mul|FloorDiv_Div|Mod_FloorDiv|Pow_Mul"
    r"|BitOr_BitAnd|BitAnd_BitOr|BitXor_BitOr|LShift_RShift|RShift_LShift)$)",
    r"core/ReplaceComparisonOperator_(?!(Lt_LtE|Lt_GtE|LtE_Lt|LtE_Gt|Gt_GtE|Gt_LtE|GtE_Gt|GtE_Lt|Eq_NotEq"
    r"|NotEq_Eq|Is_IsNot|IsNot_Is|In_NotIn|NotIn_In)$)",
    r"core/ReplaceUnaryOperator_(?!(USub_UAdd|Delete_Not|Delete_Invert|Delete_USub)$)",
]


def slug(module: str) -> str:
    return module.replace("/", "_").removesuffix(".py")


def config_text(module: str) -> str:
    tests, timeout = MODULES[module]
    command = ["env", "PYTEST_DISABLE_PLUGIN_AUTOLOAD=1", *pytest_command(module), "-x", *tests]
    excludes = ", ".join(_toml_string(e) for e in EXCLUDE)
    return (
        "[cosmic-ray]\n"
        f'module-path = "{module}"\n'
        f"timeout = {float(timeout)}\n"
        "excluded-modules = []\n"
        f'test-command = "{shlex.join(command)}"\n\n'
        '[cosmic-ray.distributor]\nname = "local"\n\n'
        f"[cosmic-ray.filters.operators-filter]\nexclude-operators = [{excludes}]\n"
    )


def pytest_command(module: str) -> list[str]:
    """pytest without its plugins' autoload (half the start-up time of a mutant's run), with
    pytest-qt for the app's modules."""
    qt = ["-p", "pytestqt.plugin"] if module.startswith("app/") else []
    return [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *qt]


def _toml_string(text: str) -> str:
    """A TOML literal string (no escapes: the regular expressions' backslashes stay)."""
    assert "'" not in text
    return f"'{text}'"


def cosmic(*args: str) -> None:
    tool = Path(sys.executable).with_name(args[0])
    subprocess.run([str(tool), *args[1:]], cwd=ROOT, check=True)


def run(modules: list[str]) -> int:
    """Mutate and test each module afresh (sequentially)."""
    SESSIONS.mkdir(exist_ok=True)
    for module in modules:
        if module not in MODULES:
            raise SystemExit(f"mutation_score: no test selection for {module}; known: {', '.join(MODULES)}")
        if module.startswith("app/") and not (os.environ.get("DISPLAY") or os.environ.get("QT_QPA_PLATFORM")):
            raise SystemExit(f"mutation_score: {module}'s tests need a display: run under xvfb-run -a")
        config, session = SESSIONS / f"{slug(module)}.toml", SESSIONS / f"{slug(module)}.sqlite"
        config.write_text(config_text(module))
        session.unlink(missing_ok=True)
        if not baseline_passes(module):
            raise SystemExit(f"mutation_score: the tests of {module} fail without a mutant; fix them first")
        cosmic("cosmic-ray", "init", str(config), str(session))
        cosmic("cr-filter-operators", str(session), str(config))
        skip_annotations(module, session)
        print(f"mutation_score: {module}: {len(results(module)[0])} mutants to run", flush=True)
        cosmic("cosmic-ray", "exec", str(config), str(session))
    print(table(modules))
    return 0


def baseline_passes(module: str) -> bool:
    """The module's tests pass on the module as it is (no mutant): else every mutant would
    count as killed."""
    tests, _ = MODULES[module]
    env = {**os.environ, "PYTEST_DISABLE_PLUGIN_AUTOLOAD": "1"}
    return subprocess.run([*pytest_command(module), *tests], env=env).returncode == 0


def rerun(modules: list[str]) -> int:
    """Run each module's survivors again (after tests were added; the module itself must be
    unchanged since its session began, as the mutants' positions refer to it)."""
    import sqlite3

    for module in modules:
        config, session = SESSIONS / f"{slug(module)}.toml", SESSIONS / f"{slug(module)}.sqlite"
        config.write_text(config_text(module))  # the test selection as it now is
        if not baseline_passes(module):
            print(f"mutation_score: the tests of {module} fail without a mutant; not run again", flush=True)
            continue
        with sqlite3.connect(session) as db:
            cleared = db.execute("DELETE FROM work_results WHERE lower(test_outcome) = 'survived'").rowcount
        print(f"mutation_score: {module}: {cleared} survivors to run again", flush=True)
        cosmic("cosmic-ray", "exec", str(config), str(session))
    print(table(modules))
    return 0


def annotation_spans(module: str) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """(start, end) (line, column) of every annotation in the module: with ``from __future__
    import annotations`` they are strings never evaluated, so a mutant inside one is
    equivalent by construction (``int | None`` -> ``int & None``)."""
    import ast

    source = (ROOT / module).read_text()
    tree = ast.parse(source)
    assert "from __future__ import annotations" in source, f"{module}: annotations are evaluated"
    nodes = []
    for node in ast.walk(tree):
        if isinstance(node, ast.arg | ast.AnnAssign) and node.annotation is not None:
            nodes.append(node.annotation)
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and node.returns is not None:
            nodes.append(node.returns)
    return [((n.lineno, n.col_offset), (n.end_lineno, n.end_col_offset)) for n in nodes]


def in_annotation(mutation, spans) -> bool:
    start, end = tuple(mutation.start_pos), tuple(mutation.end_pos)
    return any(a <= start and end <= b for a, b in spans)


def skip_annotations(module: str, session: Path) -> None:
    """Mark the mutants inside annotations as skipped (never run; see :func:`annotation_spans`)."""
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import WorkerOutcome, WorkResult

    spans = annotation_spans(module)
    session.with_suffix(".spans.json").write_text(json.dumps(spans))  # read while the file is intact
    with use_db(str(session), WorkDB.Mode.open) as db:
        for item in db.pending_work_items:
            if all(in_annotation(m, spans) for m in item.mutations):
                db.set_result(item.job_id, WorkResult(worker_outcome=WorkerOutcome.SKIPPED, output="annotation"))


def results(module: str) -> tuple[list, list]:
    """(mutants run or to run, their results or None) of a module's session, filtered ones left out."""
    from cosmic_ray.work_db import WorkDB, use_db
    from cosmic_ray.work_item import WorkerOutcome

    session = SESSIONS / f"{slug(module)}.sqlite"
    if not session.exists():
        return [], []
    with use_db(str(session), WorkDB.Mode.open) as db:
        done = {item.job_id: result for item, result in db.completed_work_items}
        items = [item for item in db.work_items]
    kept = [(i, done.get(i.job_id)) for i in items]
    kept = [(i, r) for i, r in kept if r is None or r.worker_outcome != WorkerOutcome.SKIPPED]
    return [i for i, _ in kept], [r for _, r in kept]


def changed_lines(diff: str) -> tuple[str, str]:
    """(the line taken out, the line put in) of a mutant's diff, stripped."""
    minus = [line[1:].strip() for line in diff.splitlines() if line.startswith("-") and not line.startswith("---")]
    plus = [line[1:].strip() for line in diff.splitlines() if line.startswith("+") and not line.startswith("+++")]
    return " / ".join(minus), " / ".join(plus)


def equivalents() -> list[dict]:
    """The judged equivalents: module, operator, line before and after, optionally the
    function (``definition``, for a line written alike in two places), and the reason."""
    if not EQUIVALENTS.exists():
        return []
    return tomllib.loads(EQUIVALENTS.read_text()).get("equivalent", [])


def judged(known: list[dict], module: str, mutation, before: str, after: str) -> str | None:
    """The reason a survivor is equivalent, or None when it was not judged so."""
    for e in known:
        same = (e["module"], e["operator"], e["before"], e["after"]) == (module, mutation.operator_name, before, after)
        if same and e.get("definition", mutation.definition_name) == mutation.definition_name:
            return e["reason"]
    return None


def classify(module: str) -> dict:
    """Counts of a module's session and its survivors, equivalent (with reasons) or not."""
    items, outcomes = results(module)
    known = equivalents()
    cached = SESSIONS / f"{slug(module)}.spans.json"
    if cached.exists():  # the spans of the source the session mutated (the file may be a mutant now)
        spans = [(tuple(a), tuple(b)) for a, b in json.loads(cached.read_text())]
    else:
        spans = annotation_spans(module)
    annotated = [in_annotation(item.mutations[0], spans) for item in items]
    items = [item for item, a in zip(items, annotated) if not a]
    outcomes = [result for result, a in zip(outcomes, annotated) if not a]
    counts = {"mutants": len(items), "pending": 0, "killed": 0, "survived": 0, "equivalent": [], "open": []}
    for item, result in zip(items, outcomes):
        if result is None or result.test_outcome is None:
            counts["pending"] += 1
        elif result.is_killed:
            counts["killed"] += 1
        else:
            counts["survived"] += 1
            mutation = item.mutations[0]
            before, after = changed_lines(result.diff or "")
            reason = judged(known, module, mutation, before, after)
            entry = (mutation.start_pos[0], mutation.operator_name, before, after, result.diff or "")
            if reason is not None:
                counts["equivalent"].append((*entry, reason))
            else:
                counts["open"].append(entry)
    return counts


def table(modules: list[str]) -> str:
    rows = [
        "| module | mutants | killed | survived | equivalent | non-equivalent survivors | goal (<= 10%) |",
        "|---|---:|---:|---:|---:|---:|---|",
    ]
    notes = []
    for module in modules:
        c = classify(module)
        if not c["mutants"]:
            rows.append(f"| `{module}` | not run | | | | | |")
            continue
        non_equivalent = c["mutants"] - len(c["equivalent"]) - c["pending"]
        share = len(c["open"]) / non_equivalent if non_equivalent else 0.0
        pending = f" ({c['pending']} not run)" if c["pending"] else ""
        verdict = "met" if share <= GOAL and not c["pending"] else "NOT met"
        rows.append(
            f"| `{module}` | {c['mutants']}{pending} | {c['killed']} | {c['survived']} | {len(c['equivalent'])} "
            f"| {len(c['open'])} ({100 * share:.1f}%) | {verdict} |"
        )
        for line, operator, before, after, _, reason in c["equivalent"]:
            notes.append(f"- `{module}:{line}` {operator.split('/')[-1]}: `{before}` -> `{after}`: {reason}")
    out = "\n".join(rows)
    if notes:
        out += "\n\nSurvivors judged equivalent:\n" + "\n".join(notes)
    return out


def survivors(module: str) -> str:
    c = classify(module)
    return "\n".join(f"{module}:{line} {operator}\n{diff}" for line, operator, _, _, diff in c["open"])


def main(argv: list[str]) -> int:
    if argv[:1] == ["run"]:
        return run(argv[1:] or list(MODULES))
    if argv[:1] == ["rerun"]:
        return rerun(argv[1:] or list(MODULES))
    if argv[:1] == ["survivors"]:
        for module in argv[1:] or list(MODULES):
            print(survivors(module))
        return 0
    print(table(argv or list(MODULES)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
