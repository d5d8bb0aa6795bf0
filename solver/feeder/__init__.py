"""Parts feeders on a belt (book ch. 5): the maps of fences and their simulation."""
