"""Drivers: load/displacement control and the PFEM time loop."""
