"""Closed-loop simulator: a simulated world written in the standard file formats, with truth."""
