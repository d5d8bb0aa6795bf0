"""Scenes: one pushing scene, the questions asked of it, each answered by the cheapest
model that reaches the accuracy asked for (issue 27)."""
