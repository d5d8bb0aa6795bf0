"""Request and response models of the jobs (``/v1/jobs``)."""

from __future__ import annotations

from typing import Any, Literal, get_args

from pydantic import Field

from service.common.fields import Strict
from service.common.responses import Out

Operation = Literal[
    "cor_locus", "cor_membership", "cor_solve", "cor_tripod_statistics", "cor_sketch", "push_align",
    "push_disk_encounter", "spiral_critical_radius", "spiral_schedule", "feeder_map", "feeder_simulate",
    "feeder_design", "feeder_catalogue", "scenes_analyze",
]
State = Literal["queued", "running", "succeeded", "failed", "cancelled"]

DEFERRABLE_OPERATIONS: tuple[str, ...] = get_args(Operation)
"""The operations a job can run (each route module's ``DEFERRABLE``; a test checks the two
agree)."""


class JobRequest(Strict):
    model_config = {"json_schema_extra": {"examples": [{
        "operation": "feeder_design",
        "body": {"part": {"vertices": [[0, 0], [3, 0], [3.5, 1.5], [1.5, 2.5], [-0.5, 1.2]],
                          "center_of_mass": [1.4, 1.0]},
                 "angles": {"min": 0.349, "max": 1.222, "step": 0.0174533}, "mu_c": 0.25, "alternate": False},
    }]}}

    operation: Operation = Field(description="The operation to run, by its operation id (e.g. `feeder_design` "
                                 "is POST /v1/feeder/design).")
    body: dict[str, Any] = Field(description="The operation's request body, as its route takes it; checked at once "
                                 "(422 at body.body.<field>). Its `time_limit_s` may go up "
                                 "to the jobs' cap (PESHKIN_JOB_MAX_TIME_S, 3600 s) and counts from the job's start; "
                                 "left out, the cap. The answer is JSON.")


class JobProgressOut(Out):
    stage: Literal["queued", "waiting", "running", "finished"] = Field(
        description="Where the job is: queued (not started), waiting (started, waiting for a solver slot: jobs wait "
        "behind every waiting request and hold at most all but one of the server's slots), running, finished.")
    fraction: float | None = Field(description="Estimated fraction done while running (its time so far over the "
                                   "run time predicted when it started, from the operation's measured jobs, or its "
                                   "requests before the first job; at most 0.99); 0 while waiting; 1 when finished; "
                                   "null when queued or with nothing measured yet. The same from every web process.")
    eta_s: float | None = Field(description="Estimated seconds to the end while running (same estimate); null when "
                                "unknown.")
    estimated: bool = Field(description="True: fraction and eta_s come from past run times of the operation, not "
                            "from the job's own progress.")


class JobOut(Out):
    id: str = Field(description="The job's id (32 hex digits).")
    location: str = Field(description="Where to ask for it: /v1/jobs/<id>.")
    operation: Operation = Field(description="The operation it runs.")
    state: State = Field(description="queued (waiting to start), running, succeeded (the operation answered 200), "
                         "failed (it answered an error, or could not run: see status_code and message), cancelled.")
    created_at: str = Field(description="When it was submitted (ISO 8601, UTC).")
    started_at: str | None = Field(description="When it last started running (ISO 8601, UTC); null before.")
    finished_at: str | None = Field(description="When it ended (ISO 8601, UTC); null before.")
    expires_at: str | None = Field(description="When it and its answer will be deleted (ISO 8601, UTC; "
                                   "PESHKIN_JOB_TTL_S after it ended); null before it ends.")
    attempts: int = Field(description="Times it was started (more than 1: its server or web process was lost while "
                          "it ran, and it was started again).")
    message: str = Field(description="What happened, in words (empty for a plain success).")
    cancel_requested: bool = Field(description="True once its cancellation was asked while it ran (its worker is "
                                   "ended within about a second; the state then becomes cancelled).")
    progress: JobProgressOut = Field(description="How far it is.")
    status_code: int | None = Field(description="The HTTP status the operation answered (200, or e.g. 504 with what "
                                    "was finished, 422); null until it ends, and for a cancelled job.")
    result: dict[str, Any] | None = Field(description="The operation's JSON answer (its error body when status_code "
                                          "is not 200); null until it ends, in lists, and for a cancelled job.")


class JobListOut(Out):
    jobs: list[JobOut] = Field(description="Your jobs, newest first (at most `limit`), without their results.")
