"""POST /v1/push/quasistatic, /v1/push/align and /v1/push/disk-encounter: quasi-static speeds (book 6.8) and gross motions (3.4, 4.3, 4.4)."""
