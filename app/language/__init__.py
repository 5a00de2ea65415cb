"""Languages: the words the app shows, their catalogs (Babel/gettext), numbers written as each reader writes
them, and a pseudo-locale that shows any text left untranslated.

The app speaks English (the catalogs' message ids); each browser's messages are translated on their way to
it (:mod:`app.guards.language`), so a follower reading Spanish follows a lecturer reading German.
"""
