"""Independent validation of estimated orbits: satellite laser ranging, overlaps, references."""
