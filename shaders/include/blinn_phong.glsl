// Blinn-Phong reflection, as the paper renders (§6): ambient + diffuse + specular with the
// half vector. Lighting is two-sided because open surfaces are seen from both sides and patch
// orientation is not guaranteed consistent.
#ifndef TESSERA_BLINN_PHONG_GLSL
#define TESSERA_BLINN_PHONG_GLSL

vec3 blinnPhong(vec3 normal, vec3 toEye, vec3 toLight, vec3 lightColor, vec3 ambient,
                vec3 diffuse, vec3 specular, float shininess) {
  vec3 n = dot(normal, toEye) < 0.0 ? -normal : normal;
  vec3 h = normalize(toEye + toLight);
  float nDotL = max(dot(n, toLight), 0.0);
  float nDotH = max(dot(n, h), 0.0);
  float spec = nDotL > 0.0 ? pow(nDotH, shininess) : 0.0;
  return ambient + lightColor * (diffuse * nDotL + specular * spec);
}

#endif
