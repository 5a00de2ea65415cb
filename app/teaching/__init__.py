"""Teaching: lectures and following them, presenter mode and its broadcast, state texts.

What a lecturer uses to take a room through the motions; nothing here serves or draws.
"""
