"""Files in and out: atomic writes and output paths, the writers' registry of result formats,
images and the self-contained HTML report page.

Above :mod:`targetacq.base` only: formats and files, no model.
"""
