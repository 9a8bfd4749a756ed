"""``rtc stability``: numerical stability of every variant on stiff and extreme cases.

Each case (``cases_scale``, ``cases_rays``, ``cases_transforms``, ``cases_refraction``,
``cases_degenerate``) runs through a variant's book API and is compared with an oracle
computed exactly or in high precision (``oracle``), then classified (``model.Verdict``):
exact, within tolerance (with the measured error), wrong, non-finite or crashed. ``suite``
picks the variants and runs the cases; ``runfile`` writes the run under ``results/runs/``;
``table`` shows it in the terminal and in the harness report. ``scenes`` builds what the
cases render.
"""
