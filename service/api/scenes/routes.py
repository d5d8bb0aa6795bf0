"""``POST /v1/scenes/analyze``: one scene, its questions, each answered by the cheapest model
that reaches the accuracy asked for (:func:`solver.analyze_scene`).

The job runs in a solver worker: request -> problem (:mod:`service.api.scenes.convert`) ->
one solver call with the request's budget -> response. An analysis whose time limit was
reached before any answer is a 504 with what there is; one that answered some questions is
a 200 whose other answers say "time_limited" or "not_run".
"""

from __future__ import annotations

from fastapi import APIRouter, Request
from fastapi.responses import Response

from service.api.scenes.convert import analyze_response, scene_problem
from service.api.scenes.schemas import SceneAnalyzeRequest, SceneAnalyzeResponse
from service.common.bodies import BodyRoute
from service.common.inputs import located
from service.common.responses import IN_WORKER
from service.errors import nothing_computed
from service.runtime.deadline import Deadline
from service.runtime.deferred import Deferrable, request_only
from service.runtime.jobs import runner
from solver import analyze_scene

router = APIRouter(tags=["scenes"], route_class=BodyRoute)


@router.post(
    "/v1/scenes/analyze",
    operation_id="scenes_analyze",
    summary="Answer questions about one pushing scene with the cheapest model that is accurate enough",
    response_model=SceneAnalyzeResponse,
    responses=IN_WORKER,
)
async def scenes_analyze(req: SceneAnalyzeRequest, request: Request) -> Response:
    """Where the COR can be, whether the pusher sticks or slips, how far to push to align,
    whether the speed is quasi-static, which fence aligns the part, the feeder design: each
    answered by the cheapest model (closed form, the circumscribing disk's bound, certified
    optimisation of the polygon, a design checked by simulation) that reaches the accuracy
    asked for, with the model, its error bound and its cost, and what one answer computed
    reused by the next."""
    kinds = ",".join(sorted({f"{q.ask}:{q.accuracy}" for q in req.questions}))
    return await runner(request).expensive_job(request, analyze_job, req, time_limit_s=req.time_limit_s,
                                               cost_key=kinds, anytime=True)


def analyze_job(req: SceneAnalyzeRequest, deadline: Deadline) -> SceneAnalyzeResponse:
    budget = deadline.budget()
    problem, warnings = scene_problem(req)
    with located():
        analysis = analyze_scene(problem, budget)
    body = analyze_response(analysis, warnings, budget.elapsed() * 1e3)
    if not any(a.status == "answered" for a in analysis.answers):
        raise nothing_computed("the first answer", budget.limit_s, budget.elapsed(), body.model_dump(mode="json"))
    return body


DEFERRABLE = {
    "scenes_analyze": Deferrable("POST /v1/scenes/analyze", SceneAnalyzeRequest, analyze_job, request_only),
}
"""The operations ``POST /v1/jobs`` runs later (service.runtime.deferred)."""
