"""``python -m targetacq``: the ``targetacq`` command."""

from targetacq.cli import main

if __name__ == "__main__":
    main()
