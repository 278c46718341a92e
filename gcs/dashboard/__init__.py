"""The rescue centre's live map: a browser page fed from the mission's public Zenoh keys.

Two sides. In the ground station (:mod:`gcs.dashboard.gcs_link`): every vehicle's status, the event log with its
alerts, and the simulated flood's true edge go out on Zenoh, and operator requests come in. In the dashboard
process (``python -m gcs.dashboard``, which the mission also starts for itself): a Zenoh client
(:mod:`gcs.dashboard.feed`) fills a :class:`gcs.dashboard.model.DashboardModel`, and an ASGI app
(:mod:`gcs.dashboard.app`, Starlette on uvicorn) serves the page, its vendored Leaflet, a Server-Sent-Events stream,
the downloads and, with a token, the operator commands. The page needs nothing from the internet.
"""
