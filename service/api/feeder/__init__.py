"""POST /v1/feeder/map and /v1/feeder/simulate (book ch. 5)."""
