"""A structure-aware fuzzer of kcheck's promise (issue 13): for every input, exit 0/1 for valid
scenes and 2 with a located message for bad ones, no traceback, no "internal error", no check
crash on input the loader accepted, no valid scene lost from a mixed batch, bounded time and
memory, and nothing on stderr but kcheck's own error lines.

Inputs come in six kinds, each generated from ``(seed, kind, index)`` alone, so any input is
reproducible from the numbers printed with it (:mod:`tests.fuzz.campaign`):

* ``mutation`` -- every fixture scene mutated on its parsed data (retyped, renamed, deleted,
  duplicated values, unknown keys, odd strings), or rewritten equivalently (key order, style,
  comments, aliases, encodings, names, order of supports, units) where the verdict must stay
  the fixture's own; text-level damage on top;
* ``extreme`` -- numbers at the edges of float and of the documented ranges in every numeric
  field (±inf, nan, 1e±308, subnormals, overflowing vectors, huge and tiny masses);
* ``yaml`` -- alias bombs, recursive aliases, deep nesting, huge flow lists and files, NUL
  bytes, bad encodings, byte-order marks, merge keys, odd keys, tags, several documents;
* ``fs`` -- dangling and looping symlinks, unreadable files and folders, devices, FIFOs,
  sockets, folders named like scenes, long paths, odd file names, mesh paths that escape;
* ``mesh`` -- truncated, garbage, open, inverted, flat, NaN, huge and mislabelled meshes,
  STEP garbage;
* ``cli`` -- bad options, ``--select`` oddities, unwritable and conflicting outputs, bad
  configuration, every command on bad input.

Scene inputs run as mixed batches (with valid fixture copies) in one ``kcheck check --format
json`` process each; :mod:`tests.fuzz.harness` judges every scene of the batch and the
process as a whole, and narrows a batch-level failure down to the input that caused it.
"""
