"""POST /v1/mpp/particle: Newton vs minimum power for the particle of book 2.5."""
