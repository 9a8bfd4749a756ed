"""The benchmark harness: renders scenes through the variants and measures them (time,
allocations, image error); ``results/`` keeps what it measured and its report.

Rooms, from the top: ``report`` (``rtc report`` and ``rtc compare``), ``sections`` (the
bench's sections, one table and one package each: measure, report, plot), ``document`` (what
the report is written in: its document model, summary and plot helpers), ``engine`` (a bench
run: its plan, jobs in fresh processes, run files), ``instruments`` (what measures: CPU and
memory, allocations, rays, image error, POV-Ray), ``scenery`` (the scenes it renders and the
meshes and textures they use); ``stability`` (``rtc stability``) and ``numba_targets``
(``rtc bench --numba-targets``) apart.
"""
