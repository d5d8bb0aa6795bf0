"""POST /v1/spiral/critical-radius and /v1/spiral/schedule: spiral localization of a disk (book 4.5)."""
