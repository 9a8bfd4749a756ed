"""What the report is written in: its document model and outputs (``model``), the summary
and cell texts every section shares (``summary``), what a run says about itself
(``runinfo``), and what every plot shares (``plotting``)."""
