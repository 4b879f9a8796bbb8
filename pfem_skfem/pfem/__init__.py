"""PFEM geometry: particles, alpha-shape detection, remeshing, state mapping (thesis Ch 2)."""
