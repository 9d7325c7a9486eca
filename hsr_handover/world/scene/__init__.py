"""SDFormat text for the parametric parts of the scene (table, objects, person), made from
scenario numbers. Plain string builders: no Drake here; the station parses what they return."""
