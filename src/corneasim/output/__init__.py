"""Results directories, ParaView files, plots and reports."""
