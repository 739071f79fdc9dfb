"""Eigen problems: undamped modes and their checks, modal basis and projection, complex and branch modes."""
