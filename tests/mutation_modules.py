"""The test selection of each module under mutation testing (:mod:`tests.mutation_score`).

A module's entry names the tests that must catch its mutants, fast ones first (pytest stops
at the first failure), and the seconds after which a mutant's run counts as a hang. Add a
module here to run it: ``python -m tests.mutation_score run MODULE``.
"""

from __future__ import annotations

#: module -> (tests that must catch its mutants, seconds before a mutant's run counts as a hang)
MODULES: dict[str, tuple[list[str], float]] = {
    "core/edits/clip.py": (["tests/test_clip_edges.py", "tests/test_clip.py"], 60),
    "core/analysis/contacts.py": (["tests/test_contacts.py", "tests/test_mirror_contacts.py"], 60),
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
    "core/model/channels.py": (
        [
            "tests/test_channels.py",
            "tests/test_joint_transforms.py",
            "tests/test_curves.py",
            "tests/test_curves_mirror_blind_spots.py",
        ],
        60,
    ),
    "core/analysis/curves.py": (
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
    "core/edits/mirror.py": (
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
    "app/scene/drawable.py": (["tests/test_scene_drawable_mutants.py", "tests/test_scene_world_box.py"], 60),
    "app/scene/figure.py": (["tests/test_scene_figure_mutants.py", "tests/test_scene_drawable_mutants.py"], 60),
    "app/scene/highlight.py": (["tests/test_scene_highlight_mutants.py"], 60),
    "app/scene/problem_marks.py": (["tests/test_scene_problem_marks_mutants.py"], 60),
    "app/scene/ghost_layer.py": (["tests/test_scene_ghost_layer_mutants.py"], 60),
    # the error legend: its texture to the pixel, its quad and its pixels drawn off screen
    # (no scene), then the ghost layers' legend tests (the tiny figure and its moved copy compared)
    "app/scene/legend.py": (
        [
            "tests/test_scene_legend_mutants.py",
            "tests/test_scene_ghost_layer_mutants.py::test_the_legends_labels_run_from_zero_to_the_top_in_three_digits",
            "tests/test_scene_ghost_layer_mutants.py::test_the_legend_is_a_bar_in_the_maps_colours_its_labels_and_title_in_one_texture",
            "tests/test_scene_ghost_layer_mutants.py::test_the_legend_is_drawn_at_the_views_right_upright",
        ],
        60,
    ),
    # the view's GPU parts: small parts drawn off screen (their arrays, actors and pixels), then
    # the imposters' first picture tests (a second in all: no window, no real file), and the
    # scene's parts unshifted
    "app/scene/vtk_parts.py": (
        [
            "tests/test_vtk_parts_arrays.py",
            "tests/test_vtk_parts_pictures.py",
            "tests/test_app_drawables.py::test_imposter_spheres_cover_their_disc_and_a_missing_point_draws_nothing",
            "tests/test_app_drawables.py::test_imposter_bones_run_from_joint_to_joint",
            "tests/test_scene_world_box.py::test_every_part_sends_its_points_unshifted_and_a_figure_far_from_the_origin_draws_the_same",
        ],
        60,
    ),
    # the screen-space quads (labels and the legend's quad): the label atlas, quads and their
    # placement on their own (no scene), their texels drawn off screen, the legend's quad,
    # then the overlays' labels and the labels in a scene of the tiny figure (three seconds)
    "app/scene/labels.py": (
        [
            "tests/test_vtk_parts_arrays.py::test_labels_are_packed_into_one_texture_each_text_as_vtk_draws_it",
            "tests/test_vtk_parts_arrays.py::test_labels_default_to_white_13_point_text",
            "tests/test_vtk_parts_arrays.py::test_an_empty_text_and_no_texts_keep_a_texture",
            "tests/test_vtk_parts_arrays.py::test_new_texts_rebuild_the_texture",
            "tests/test_vtk_parts_arrays.py::test_device_points_map_the_view_onto_minus_one_to_one_at_the_near_depth",
            "tests/test_vtk_parts_arrays.py::test_device_points_of_a_view_of_no_width_or_height_are_finite",
            "tests/test_vtk_parts_arrays.py::test_labels_are_placed_at_their_anchors_plus_the_offset_on_whole_pixels_and_hidden_off_screen",
            "tests/test_vtk_parts_arrays.py::test_quads_are_written_again_only_when_they_or_the_view_change",
            "tests/test_vtk_parts_arrays.py::test_labels_draw_last_in_the_opaque_pass_with_the_texels_own_colours_and_no_bounds",
            "tests/test_vtk_parts_pictures.py::test_labels_show_their_texels_on_whole_pixels_in_front_of_everything_and_hidden_ones_nothing",
            "tests/test_vtk_parts_pictures.py::test_a_labels_empty_texels_write_no_depth_so_what_is_drawn_after_it_shows_between_its_letters",
            "tests/test_scene_legend_mutants.py",
            "tests/test_app_overlays_mutants.py",
            "tests/test_scene_labels.py",
        ],
        60,
    ),
    # the view's overlays (issue 24): a stand-in scene with a bare renderer, a tiny synthetic motion
    "app/scene/overlays.py": (["tests/test_app_overlays_mutants.py"], 60),
    # the dock policy: plain widgets and tabbed docks of a small main window (the app's docks'
    # own tests open the real window on a real take: seconds a mutant)
    "app/docks/frame_follow.py": (["tests/test_app_frame_follow_mutants.py"], 60),
    # the inspector dock on its own: a bare Inspector over a state with a small random motion
    "app/docks/inspector.py": (["tests/test_docks_inspector_mutants.py"], 60),
    # the inspector's text: a bare widget (slots, layout, painting, selection, keys, menu)
    "app/docks/rich_text.py": (["tests/test_app_rich_text.py", "tests/test_app_rich_text_on_screen.py"], 60),
    # the timeline's slider: a bare widget (ranges, frames <-> pixels, flags, pixels, mouse, repaints)
    "app/docks/range_slider.py": (["tests/test_app_range_slider_mutants.py"], 60),
    # the Curves and Error docks' plot: a bare widget on a small synthetic table
    "app/docks/timeplot.py": (["tests/test_app_timeplot_mutants.py", "tests/test_app_timeplot_cursor.py"], 60),
    # the layout's rules on a small main window of plain widgets (the real window's layout tests
    # open a real take at two sizes: ten seconds a mutant)
    "app/window/layout.py": (["tests/test_app_layout_mutants.py"], 60),
    # the view's widget kind: environments given as dicts, the process-wide choice reset per test
    "app/scene/render_widget.py": (["tests/test_app_render_widget_mutants.py"], 60),
    # the classroom's drawing: a tiny synthetic motion, a stand-in scene with bare renderers
    "app/scene/teach_overlay.py": (["tests/test_app_teach_overlay_mutants.py"], 60),
    # the scene itself: its list of drawables, the camera, the projection and the onion skins,
    # the planes fitted to the take's box and the labels drawn last, on the tiny figure (no window)
    "app/scene/scene.py": (
        [
            "tests/test_scene_scene_mutants.py",
            "tests/test_scene_render_mutants.py",
            "tests/test_scene_world_box.py",
            "tests/test_scene_labels.py",
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
