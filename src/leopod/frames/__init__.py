"""Reference frames: satellite attitude and antenna frames (ITRF<->GCRF comes with the dynamics engine)."""
