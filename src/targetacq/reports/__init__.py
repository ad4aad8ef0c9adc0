"""Figures and report content made from runs of the model (the page itself is written by
:mod:`targetacq.io.html_report`)."""
