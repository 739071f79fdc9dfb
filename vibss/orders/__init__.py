"""Rotating machinery: rotating unbalance and engine-order forces and moments against shaft speed,
their steady-state response over a speed range (order cuts, critical speeds, Campbell diagram) and a
run-up in the time domain."""

from __future__ import annotations

from .api import order_response, run_up
from .kernels import critical_speeds
from .result import OrderResponse
from .sources import OrderForce, Unbalance

__all__ = ["OrderForce", "OrderResponse", "Unbalance", "critical_speeds", "order_response", "run_up"]
