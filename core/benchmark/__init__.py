"""``gmr bench`` machinery: the paper's benchmark (section 6, Figure 4) in one run.

- :mod:`core.benchmark.data`: the real BVH files, grouped by skeleton, tiled to N frames.
- :mod:`core.benchmark.configs`: configurations C_k (k chosen joints as roots).
- :mod:`core.benchmark.timing`: best-of-N timings with their noise; peak memory.
- :mod:`core.benchmark.peers`: other Python BVH libraries, timed and checked.
- :mod:`core.benchmark.runner`: one run, returning the results as a dict (the JSON).
- :mod:`core.benchmark.report`: tables, JSON, the plot.

:mod:`core.benchmark.startup` times the command lines' start-up (``gmr --help`` beside
``python -c "import numpy"``).

The JSON holds at least ``frames``, ``joints``, ``bvh_us_per_frame``,
``yardstick_us_per_frame``, ``configs`` (``{"k", "us_per_frame", "ratio_to_bvh", ...}``),
``parse_mb_per_s``, ``numpy_parse_mb_per_s`` and ``peers`` (``{"name", "version",
"us_per_frame", ...}``), plus the Euler-angle variants, operations, memory, the machine
and a ``definitions`` entry saying what each ratio means. docs/benchmark.md has a run.
"""
