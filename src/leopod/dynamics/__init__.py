"""Force models of the orbit dynamics (gravity field, tides, third bodies, relativity, ...)."""
