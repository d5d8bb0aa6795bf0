"""POST /v1/cor/locus and POST /v1/cor/membership: the COR locus (book 3.3) and whether a point is a COR."""
