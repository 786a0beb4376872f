"""From a scene to its analysed retraction cases, and what is built on them (sanity
warnings, kcheck suggest)."""
