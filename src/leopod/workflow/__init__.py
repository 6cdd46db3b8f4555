"""The workflow layer: campaign configuration, settings, the script boundary and logging."""
