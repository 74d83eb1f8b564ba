"""Looking at models and motions: ``geometry`` (the model's shapes and frames over a motion, numpy
only), ``plots`` (figures as image files, matplotlib), ``video`` (MP4 through matplotlib and ffmpeg)
and ``viewer`` (the browser, through meshcat: ``pip install 'hovi[viewer]'``). Import the module you
need; nothing here is imported by ``import hovi``."""
