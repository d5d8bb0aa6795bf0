"""POST /v1/scenes/analyze: one pushing scene, the questions asked of it, each answered by the cheapest model that reaches the accuracy asked for."""
