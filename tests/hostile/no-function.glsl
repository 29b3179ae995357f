vec2 other(vec2 t) { return t; }
