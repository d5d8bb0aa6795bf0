"""POST /v1/jobs, GET and DELETE /v1/jobs/{id}: long work run later (service.runtime.deferred)."""
