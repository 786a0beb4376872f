"""Running checks over a repository: discovery, configuration, workers, cache, git."""
