"""Where a request's work runs, and for how long.

* :mod:`~service.runtime.deadline`: the request's deadline, from its arrival (queueing,
  solving, converting and rendering all count), and the part of it a solver may use;
* :mod:`~service.runtime.intake`: every request's arrival is noted, and it is admitted
  through the gate of requests in flight (or refused 503 at once with ``Retry-After``);
* :mod:`~service.runtime.admission`: a bounded gate of requests in flight (cheap work is
  computed in the web process, on its event loop) and the queue of expensive work, which
  admits a request only when it is predicted to start in time;
* :mod:`~service.runtime.slots`: the server's slots of expensive work (one per usable CPU),
  shared by all its web processes;
* :mod:`~service.runtime.pool`: the solver worker processes (Pebble's process pool on a
  forkserver), each with its own solver caches; a worker that dies or overruns is replaced;
* :mod:`~service.runtime.jobs`: runs a route's job (a top-level function: request in,
  response out) in a worker or in a thread, and turns what it returns or raises into the
  bytes of an HTTP answer, under the deadline; a client that goes away cancels its job.
"""
