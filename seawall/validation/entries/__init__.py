"""Validation entries: one module per entry, each defining ENTRY (see seawall.validation)."""
