"""Figures of the workflow steps (matplotlib, Agg backend)."""
