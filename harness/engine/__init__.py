"""A bench run: its plan (``plan``), the ``Bench`` that runs the sections (``bench``), each
measurement in a fresh process (``jobs``, ``child``, ``lifeline``), the budget rule (``budget``),
the figures read off a row (``figures``), the run files (``results``), the machine and who
else used it (``machine``, ``sharing``), jobs on a Dask cluster (``cluster_jobs``)."""
