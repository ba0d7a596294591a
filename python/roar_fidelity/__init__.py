"""CARLA's telemetry of ROAR's car, and our car measured against it (bench/carla_fidelity.py)."""
from .telemetry import TICK, Telemetry, TelemetryError, read_telemetry  # noqa: F401
