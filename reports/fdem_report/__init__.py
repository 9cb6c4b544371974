"""fdem validation report: reads the CSV/JSON the studies write, tabulates every
deviation from reference_data/, and draws each study's plots (HTML + PDF)."""
