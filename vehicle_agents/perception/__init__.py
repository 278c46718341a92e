"""Onboard vision: land/water segmentation of the downward camera image (paper §III-A.1, eq 5, Algorithm 1)."""
