"""Antenna-frame code-bias maps: grid, estimation from multipath, products, application."""
