"""In-flight calibration of the LEO receiver antenna (PCV by the residual method: ``pcv``)."""
