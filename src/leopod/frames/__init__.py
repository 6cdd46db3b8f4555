"""Reference frames: ITRF <-> GCRF (IAU 2006/2000A), satellite attitude and antenna frames."""
