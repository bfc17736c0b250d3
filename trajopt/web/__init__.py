"""``mpa serve``: a local web explorer of tracks, domains and motions (:mod:`trajopt.web.api`, :mod:`trajopt.web.app`).

The page and its scripts ship in ``trajopt/web/static`` (no network access needed). The server needs the optional
extra ``[serve]`` (Starlette and uvicorn); :mod:`trajopt.web.api` itself needs neither.
"""
