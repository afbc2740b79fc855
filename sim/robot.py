"""The differential-drive robot: loaded from its URDF, driven only through its wheel motors."""
from __future__ import annotations

import math
from pathlib import Path

import pybullet as p

URDF = Path(__file__).parent / "assets" / "diffdrive.urdf"
RADIUS_M = 0.15        # footprint radius
WHEEL_RADIUS_M = 0.05
WHEEL_BASE_M = 0.24    # distance between the wheels
AXLE_HEIGHT_M = 0.05
MOTOR_FORCE_N = 5.0


class DiffDriveRobot:
    """A robot in a PyBullet world; ``command(v, w)`` sets the wheel motors for forward speed v (m/s) and turn
    rate w (rad/s). Its pose comes from the physics, never set after spawning."""

    def __init__(self, client: int, x: float, y: float, yaw: float):
        self.client = client
        orientation = p.getQuaternionFromEuler((0, 0, yaw))
        self.body = p.loadURDF(str(URDF), (x, y, AXLE_HEIGHT_M), orientation, physicsClientId=client)
        joints = {p.getJointInfo(self.body, j, physicsClientId=client)[1].decode(): j
                  for j in range(p.getNumJoints(self.body, physicsClientId=client))}
        self.left, self.right = joints["left_wheel_joint"], joints["right_wheel_joint"]
        for name in ("front_caster_joint", "rear_caster_joint"):
            p.changeDynamics(self.body, joints[name], lateralFriction=0.0, rollingFriction=0.0,
                             spinningFriction=0.0, physicsClientId=client)
        for wheel in (self.left, self.right):
            p.changeDynamics(self.body, wheel, lateralFriction=1.2, physicsClientId=client)
        self.command(0.0, 0.0)

    def command(self, v: float, w: float) -> None:
        """Drive at forward speed ``v`` (m/s) and turn rate ``w`` (rad/s, counter-clockwise) via the wheel motors."""
        left, right = wheel_speeds(v, w)
        for joint, speed in ((self.left, left), (self.right, right)):
            p.setJointMotorControl2(self.body, joint, p.VELOCITY_CONTROL, targetVelocity=speed, force=MOTOR_FORCE_N,
                                    physicsClientId=self.client)

    def pose(self) -> tuple[float, float, float]:
        """(x, y, yaw) in metres and radians."""
        position, orientation = p.getBasePositionAndOrientation(self.body, physicsClientId=self.client)
        return position[0], position[1], p.getEulerFromQuaternion(orientation)[2]

    def velocity(self) -> tuple[float, float]:
        """(forward speed m/s, turn rate rad/s) measured by the physics."""
        linear, angular = p.getBaseVelocity(self.body, physicsClientId=self.client)
        yaw = self.pose()[2]
        return linear[0] * math.cos(yaw) + linear[1] * math.sin(yaw), angular[2]


def wheel_speeds(v: float, w: float) -> tuple[float, float]:
    """Left and right wheel angular speeds (rad/s) for body speed v (m/s) and turn rate w (rad/s)."""
    return (v - w * WHEEL_BASE_M / 2) / WHEEL_RADIUS_M, (v + w * WHEEL_BASE_M / 2) / WHEEL_RADIUS_M
