"""The ground station: mission runner, polygon aggregation for the rescue centre, metrics and reports."""
