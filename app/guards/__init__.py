"""Guards around viser 1.1.1's private wire: browsers' inputs and uploads, the share tunnel, the event loop,
HTTP responses (a cookie on the page).

Each replaces or wraps a private piece of the pinned viser; tests/app proves each through a real websocket.
"""
