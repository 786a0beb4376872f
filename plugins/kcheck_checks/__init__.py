"""kcheck's built-in checks, registered through the ``kcheck.checks`` entry points."""
