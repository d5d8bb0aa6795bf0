"""POST /v1/cor/solve and POST /v1/cor/tripod-statistics: motions for known pressure distributions (book 3.2-3.3, 4.1, 7)."""
