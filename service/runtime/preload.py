"""Imported once by the forkserver before it forks solver workers (see
:mod:`service.runtime.pool`): the solver stack and the routes' jobs, so that a new worker
starts with everything loaded."""

from __future__ import annotations

import service.api.feeder.routes
import service.api.locus.routes
import service.api.motion.routes
import service.api.particle.routes
import service.api.push.routes
import service.api.sketch.routes
import service.api.spiral.routes
import service.runtime.jobs  # noqa: F401
