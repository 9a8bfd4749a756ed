"""The report: ``rtc report`` (``build``: results/README.md and report.html from the run
history, every section in the table's order), ``rtc compare`` and the history (``compare``),
the report's own plots (``plots``), and the figures the README quotes (``readme_figures``)."""
