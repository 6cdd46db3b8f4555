"""Time: calendar labels and GPS weeks, time scales (GPST, TAI, TT, UTC), Earth orientation."""
