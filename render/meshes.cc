#include "render/meshes.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <vector>

#include "render/frame_state.h"

namespace ripple::render::internal {
namespace {

struct SolidVertex {
  glm::vec3 pos, normal;
};
struct WallVertex {
  glm::vec3 pos, normal;
  glm::vec2 wall;
};

void AddQuad(std::vector<SolidVertex>* v, glm::vec3 a, glm::vec3 b, glm::vec3 c,
             glm::vec3 d, glm::vec3 n) {
  for (const glm::vec3& p : {a, b, c, a, c, d}) v->push_back({p, n});
}

// Axis-aligned unit cube [-0.5, 0.5]^3.
std::vector<SolidVertex> UnitBox() {
  std::vector<SolidVertex> v;
  for (int axis = 0; axis < 3; ++axis) {
    for (float s : {-0.5f, 0.5f}) {
      glm::vec3 n(0), u(0), w(0);
      n[axis] = s > 0 ? 1.f : -1.f;
      u[(axis + 1) % 3] = 0.5f;
      w[(axis + 2) % 3] = 0.5f;
      const glm::vec3 c = n * 0.5f;
      AddQuad(&v, c - u - w, c + u - w, c + u + w, c - u + w, n);
    }
  }
  return v;
}

// Cylinder of radius 1 from z = 0 to z = 1, with caps.
std::vector<SolidVertex> UnitCylinder(int segments) {
  std::vector<SolidVertex> v;
  const float step = 2.0f * 3.14159265f / segments;
  for (int i = 0; i < segments; ++i) {
    const float a0 = i * step, a1 = (i + 1) * step;
    const glm::vec3 p0(std::cos(a0), std::sin(a0), 0),
        p1(std::cos(a1), std::sin(a1), 0);
    const glm::vec3 up(0, 0, 1);
    const glm::vec3 n = glm::normalize(p0 + p1);
    AddQuad(&v, p0, p1, p1 + up, p0 + up, n);
    v.push_back({glm::vec3(0, 0, 1), up});
    v.push_back({p0 + up, up});
    v.push_back({p1 + up, up});
    v.push_back({glm::vec3(0), -up});
    v.push_back({p1, -up});
    v.push_back({p0, -up});
  }
  return v;
}

void UploadSolid(Mesh* mesh, const std::vector<SolidVertex>& v) {
  mesh->vao.Create();
  mesh->vbo.Create();
  glBindVertexArray(mesh->vao.id());
  glBindBuffer(GL_ARRAY_BUFFER, mesh->vbo.id());
  glBufferData(GL_ARRAY_BUFFER, v.size() * sizeof(SolidVertex), v.data(),
               GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(SolidVertex),
                        reinterpret_cast<void*>(0));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(SolidVertex),
                        reinterpret_cast<void*>(sizeof(glm::vec3)));
  mesh->count = static_cast<int>(v.size());
  glBindVertexArray(0);
}

}  // namespace

bool SameTank(const TankGeometry& a, const TankGeometry& b) {
  return a.size_x == b.size_x && a.size_y == b.size_y &&
         a.wall_height == b.wall_height && a.water_level == b.water_level;
}

void ModelUniforms::Resolve(const Program& p) {
  tank_from_model = p.Uniform("u_tank_from_model");
  clip_from_model = p.Uniform("u_clip_from_model");
}

void TankWallsMesh::Create(float glass_thickness_m) {
  glass_thickness_m_ = glass_thickness_m;
  vao_.Create();
  vbo_.Create();
  glBindVertexArray(vao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.id());
  glBufferData(GL_ARRAY_BUFFER, 48 * sizeof(WallVertex), nullptr,
               GL_DYNAMIC_DRAW);
  for (int a = 0; a < 3; ++a) glEnableVertexAttribArray(a);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(WallVertex),
                        reinterpret_cast<void*>(0));
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(WallVertex),
                        reinterpret_cast<void*>(sizeof(glm::vec3)));
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(WallVertex),
                        reinterpret_cast<void*>(2 * sizeof(glm::vec3)));
  glBindVertexArray(0);
  tank_.reset();
}

void TankWallsMesh::Update(const TankGeometry& t) {
  if (tank_ && SameTank(*tank_, t)) return;
  tank_ = t;
  const float hx = 0.5f * t.size_x, hy = 0.5f * t.size_y, z = t.wall_height;
  std::vector<WallVertex> v;
  // Corners counter-clockwise seen from above; wall i runs from c[i] to
  // c[i + 1] with outward normal n[i].
  const glm::vec3 c[5] = {
      {-hx, -hy, 0}, {hx, -hy, 0}, {hx, hy, 0}, {-hx, hy, 0}, {-hx, -hy, 0}};
  const glm::vec3 n[4] = {{0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  for (int i = 0; i < 4; ++i) {
    const float len = glm::length(c[i + 1] - c[i]);
    const glm::vec3 up(0, 0, z);
    const WallVertex a{c[i], n[i], {0, len}}, b{c[i + 1], n[i], {len, len}},
        cc{c[i + 1] + up, n[i], {len, len}}, d{c[i] + up, n[i], {0, len}};
    for (const WallVertex& x : {a, b, cc, a, cc, d}) v.push_back(x);
  }
  // The top faces: the -y and +y walls' span the corners. Each vertex's
  // normal slot holds the direction across its wall, away from the face
  // (outwards on the outer edge, into the tank on the inner one): the
  // shader widens the faces along it to cover their edges' pixels. The uv
  // slot holds the wall's inward normal (x, y).
  const float gx = hx + glass_thickness_m_, gy = hy + glass_thickness_m_;
  const glm::vec4 tops[4] = {{-gx, -gy, gx, -hy},
                             {hx, -hy, gx, hy},
                             {-gx, hy, gx, gy},
                             {-gx, -hy, -hx, hy}};
  // Per top face: the direction from its first corner's edge (r.x, r.y)
  // outwards, for its two long edges.
  const glm::vec3 grow0[4] = {{0, -1, 0}, {-1, 0, 0}, {0, -1, 0}, {-1, 0, 0}};
  // The walls' outward normals; the uv slot holds the inward one.
  const glm::vec3 n_top[4] = {{0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  for (int i = 0; i < 4; ++i) {
    const glm::vec4& r = tops[i];
    const glm::vec2 p[4] = {{r.x, r.y}, {r.z, r.y}, {r.z, r.w}, {r.x, r.w}};
    // The long edge through the first corner: x = r.x (corners 0 and 3)
    // for the x walls (i = 1, 3), which run along y; y = r.y (corners 0
    // and 1) for the y walls.
    const bool first_edge[2][4] = {{true, true, false, false},
                                   {true, false, false, true}};
    WallVertex q[4];
    for (int k = 0; k < 4; ++k)
      q[k] = {{p[k].x, p[k].y, z},
              first_edge[i % 2][k] ? grow0[i] : -grow0[i],
              {-n_top[i].x, -n_top[i].y}};
    for (const int k : {0, 1, 2, 0, 2, 3}) v.push_back(q[k]);
  }
  glBindBuffer(GL_ARRAY_BUFFER, vbo_.id());
  glBufferSubData(GL_ARRAY_BUFFER, 0, v.size() * sizeof(WallVertex), v.data());
}

void SolidMeshes::Create() {
  UploadSolid(&box_, UnitBox());
  UploadSolid(&cylinder_, UnitCylinder(24));
}

void SolidMeshes::Draw(const SceneInputs& scene, const ModelUniforms& p,
                       const glm::dmat4& clip_from_tank, bool obstacles,
                       bool pen, const PenGrow& pen_grow) const {
  auto draw = [&](const Mesh& mesh, const glm::dmat4& tank_from_model) {
    SetUniform(p.tank_from_model, tank_from_model);
    SetUniform(p.clip_from_model, clip_from_tank * tank_from_model);
    glBindVertexArray(mesh.vao.id());
    glDrawArrays(GL_TRIANGLES, 0, mesh.count);
  };
  if (obstacles) {
    for (const Obstacle& o : scene.obstacles) {
      const glm::dvec3 size(o.size);
      if (o.shape == Obstacle::Shape::kBox) {
        draw(box_, glm::scale(glm::translate(o.tank_from_obstacle,
                                             {0.0, 0.0, 0.5 * size.z}),
                              size));
      } else {
        draw(cylinder_,
             glm::scale(o.tank_from_obstacle, {size.x, size.x, size.z}));
      }
    }
  }
  if (pen && scene.pen_visible) {
    const PenGeometry& g = scene.pen;
    const double e = g.cube_edge, r = g.shaft_radius + pen_grow.shaft_m;
    const double len = g.shaft_length + std::max(pen_grow.shaft_m, 0.0);
    draw(box_,
         glm::scale(scene.tank_from_pen, glm::dvec3(e + 2 * pen_grow.cube_m)));
    const glm::dmat4 shaft =
        glm::translate(scene.tank_from_pen, {0.0, 0.0, -0.5 * e - len});
    draw(cylinder_, glm::scale(shaft, {r, r, len}));
  }
  glBindVertexArray(0);
}

}  // namespace ripple::render::internal
