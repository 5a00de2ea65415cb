"""Uploads: a student's mesh file checked against the limits and read into a body, in a worker process.

The limits (one home for every number), the mesh reading, the worker.
"""
