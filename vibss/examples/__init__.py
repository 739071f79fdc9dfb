"""Built-in example model files (``vibss example list``; :func:`vibss.io.load_example`)."""
