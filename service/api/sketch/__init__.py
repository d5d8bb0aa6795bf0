"""POST /v1/cor/sketch: the COR sketch with pusher friction (book 4.1)."""
