"""Nonlinear mounts: the operating point under static load and its tangent model."""
