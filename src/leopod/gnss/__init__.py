"""GNSS signals, combinations, cycle slips and data quality."""
