"""What several resources of :mod:`service.api` share, so that none copies another.

* :mod:`service.common.fields`: pydantic types of request fields (points, angles, the
  push's scene fields, disk radius, polygon, time limit, friction) and the base models;
* :mod:`service.common.responses`: the error bodies (422, 504) and the ``responses`` of
  the routes;
* :mod:`service.common.numbers`: finite floats out, never NaN or infinity;
* :mod:`service.common.inputs`: domain ``InvalidInput`` errors located at request fields,
  "exactly one of", footprints;
* :mod:`service.common.scene`: the push scene (and footprint) of a request, with the
  service's warnings;
* :mod:`service.common.svg`: the view frame, clipping, colours and figure setup of the SVG
  pictures.

It may import :mod:`models`, :mod:`solver`, :mod:`service.errors` and
:mod:`service.limits`, never :mod:`service.api`.
"""
