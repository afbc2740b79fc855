"""PyBullet layer of tdp: a differential-drive robot planned by tdp among box obstacles (ARCHITECTURE §8)."""
