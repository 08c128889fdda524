// Physical and mathematical constants shared by all shaders.
const float PI = 3.14159265358979;
