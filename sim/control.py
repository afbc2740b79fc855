"""Pure-pursuit steering along the planner's successor chain, with speed and acceleration limits."""
from __future__ import annotations

import math
from dataclasses import dataclass


def wrap(angle: float) -> float:
    """Angle in (-pi, pi]."""
    return math.atan2(math.sin(angle), math.cos(angle))


@dataclass
class PurePursuit:
    """Turns a list of way points (metres) into (v, w): steer for the first point at least ``lookahead_m`` away,
    turn in place when it lies more than ``turn_in_place`` radians off the heading. Speeds are limited to
    ``max_v`` (m/s) and ``max_w`` (rad/s), their changes per second to ``max_dv`` and ``max_dw``."""

    max_v: float = 0.5
    max_w: float = 2.5
    max_dv: float = 1.5
    max_dw: float = 8.0
    lookahead_m: float = 0.3
    turn_in_place: float = math.radians(50)
    v: float = 0.0
    w: float = 0.0

    def stop(self, dt: float) -> tuple[float, float]:
        """Brake towards standstill within the acceleration limits."""
        return self._limited(0.0, 0.0, dt)

    def steer(self, pose: tuple[float, float, float], points: list[tuple[float, float]],
              dt: float) -> tuple[float, float]:
        """(v, w) towards the look-ahead point of ``points`` from ``pose`` (x, y, yaw)."""
        if not points:
            return self.stop(dt)
        x, y, yaw = pose
        target = next((q for q in points if math.hypot(q[0] - x, q[1] - y) >= self.lookahead_m), points[-1])
        distance = math.hypot(target[0] - x, target[1] - y)
        heading_error = wrap(math.atan2(target[1] - y, target[0] - x) - yaw)
        if abs(heading_error) > self.turn_in_place:
            return self._limited(0.0, 3.0 * heading_error, dt)
        v = min(self.max_v, 2.0 * distance) * math.cos(heading_error)
        w = 2.0 * v * math.sin(heading_error) / max(distance, 1e-6) + 1.0 * heading_error
        return self._limited(v, w, dt)

    def _limited(self, v: float, w: float, dt: float) -> tuple[float, float]:
        v = max(-self.max_v, min(self.max_v, v))
        w = max(-self.max_w, min(self.max_w, w))
        self.v += max(-self.max_dv * dt, min(self.max_dv * dt, v - self.v))
        self.w += max(-self.max_dw * dt, min(self.max_dw * dt, w - self.w))
        return self.v, self.w
