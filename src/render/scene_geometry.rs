//! The scene gathered on the CPU for upload ([`SceneGeometry`]): its meshes' vertices, triangles
//! and adjacency, its polygonal lights' emissive fans, lights and materials, and one
//! [`DrawCall`] per mesh and [`EmitterDraw`] per polygonal light saying where each lies.

use super::textures::gpu_material;
use crate::geometry::shadow_class::{ShadowClasses, Visibility};
use crate::geometry::shadow_view::{shader_order, LightShadow, Projection, ShadowLayout};
use crate::gpu_interface::flags::{FLAG_ONE_SIDED, FLAG_SHARED_CORNERS};
use crate::gpu_interface::slots::{MAX_SHADOWED_LIGHTS, MIXED_CLASS_BIT, SHADOWED_CLASS_BIT};
use crate::gpu_types::{DrawConstants, GpuLight, GpuMaterial, GpuPolygonLight, GpuShadowMap, Vertex};
use crate::scene::adjacency::{adjacency_patches, neighbours};
use crate::scene::{Light, MaterialKind, Mesh, Scene};
use glam::{IVec4, Mat4, Vec4};

/// One mesh's draw: where its triangles lie in the scene's buffers and what it is drawn with.
pub(super) struct DrawCall {
    /// Index of the mesh's first triangle in the scene.
    pub first_triangle: u32,
    pub first_index: u32,
    pub index_count: u32,
    /// Where this mesh's 12-index adjacency patches start in the patch index buffer.
    pub first_patch_index: u32,
    /// Back faces are culled (`Mesh::two_sided` false).
    pub one_sided: bool,
    /// Its material has no parameter map, so a flat patch's corner shades the same in every
    /// triangle that shares it: the compute placement draws those patches indexed, from
    /// `PrePassBuffers::flat_indices`.
    pub shared_corners: bool,
    pub material_index: u32,
    pub mesh_index: u32,
    /// The variant of its material kind (index into the renderer's variants).
    pub pipeline: usize,
}

impl DrawCall {
    /// `constants` with this mesh's fields: its material, its index and its flags.
    pub(super) fn set_constants(&self, constants: &mut DrawConstants) {
        constants.material_index = self.material_index;
        constants.mesh_index = self.mesh_index;
        let mesh_flags = FLAG_ONE_SIDED | FLAG_SHARED_CORNERS;
        constants.flags = (constants.flags & !mesh_flags)
            | if self.one_sided { FLAG_ONE_SIDED } else { 0 }
            | if self.shared_corners { FLAG_SHARED_CORNERS } else { 0 };
    }
}

/// The emissive geometry of one polygonal light: a triangle fan in the scene's buffers.
pub(super) struct EmitterDraw {
    pub first_index: u32,
    pub index_count: u32,
    pub light_index: u32,
}

/// The values of the shaders' MATERIAL_KIND (`Features::material_kind`).
fn material_kind_id(kind: &MaterialKind) -> u32 {
    match kind {
        MaterialKind::Lambert { .. } => 0,
        MaterialKind::BlinnPhong { .. } => 1,
        MaterialKind::Ggx { .. } => 2,
    }
}

/// The scene's point and directional lights as the shaders read them ([`ShaderLights`]).
pub fn gpu_lights(lights: &[Light], shadows: &[Option<LightShadow>]) -> ShaderLights {
    let shadow_of = |index: usize| shadows.get(index).copied().flatten();
    let mut gpu = ShaderLights::default();
    for index in shader_order(lights, |index| shadow_of(index).is_some()) {
        let shadow = shadow_of(index);
        let gpu_shadow = match shadow {
            Some(s) => IVec4::new(s.map as i32, s.radius as i32, s.slot as i32, 0),
            None => IVec4::new(-1, 0, 0, 0),
        };
        let (position, radiance, count, shadowed) = match lights[index] {
            Light::Point { position, color, intensity } => {
                (position.extend(1.0), color * intensity, &mut gpu.point_count, &mut gpu.shadowed_point_count)
            }
            Light::Directional { direction, color, intensity } => (
                direction.extend(0.0),
                color * intensity,
                &mut gpu.directional_count,
                &mut gpu.shadowed_directional_count,
            ),
            Light::Polygon(_) => continue,
        };
        *count += 1;
        *shadowed += i32::from(shadow.is_some());
        gpu.lights.push(GpuLight { position, radiance: radiance.extend(0.0), shadow: gpu_shadow });
    }
    gpu
}

/// The point and directional lights in the order the shaders number them: the point lights,
/// then the directional ones; in each, those that cast shadows first, in slot order
/// (`LightShadow::slot`: the point lights' slots come first), so that a light's slot follows
/// from its index and the four counts (shadow.glsl's `shadow_slot`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShaderLights {
    pub lights: Vec<GpuLight>,
    pub point_count: i32,
    pub directional_count: i32,
    /// The point lights that cast shadows: the first of them.
    pub shadowed_point_count: i32,
    /// The directional lights that cast shadows: the first of them.
    pub shadowed_directional_count: i32,
}

/// The shadow maps as the shaders read them.
pub fn gpu_shadow_maps(layout: &ShadowLayout) -> Vec<GpuShadowMap> {
    layout
        .maps
        .iter()
        .map(|m| {
            let (view_proj, depth) = match m.projection {
                Projection::Orthographic(view_proj) => (view_proj, Vec4::ZERO),
                Projection::Cube { near, far, .. } => (Mat4::IDENTITY, Vec4::new(near, far, 1.0, 0.0)),
            };
            let rect = Vec4::new(m.offset[0] as f32, m.offset[1] as f32, m.size as f32, m.texel_width);
            GpuShadowMap { view_proj, rect, depth }
        })
        .collect()
}

/// The scene's polygonal lights, in scene order (the shaders' `polygon_lights`).
pub fn gpu_polygon_lights(lights: &[Light]) -> Vec<GpuPolygonLight> {
    lights
        .iter()
        .filter_map(|light| match light {
            Light::Polygon(p) => {
                let mut vertices = [glam::Vec4::ZERO; 8];
                for (out, v) in vertices.iter_mut().zip(p.vertices()) {
                    *out = v.extend(1.0);
                }
                Some(GpuPolygonLight {
                    vertices,
                    normal: p.normal.extend(p.area),
                    radiance: p.radiance().extend(0.0),
                    info: glam::IVec4::new(p.count as i32, 0, 0, 0),
                })
            }
            _ => None,
        })
        .collect()
}

/// The scene as its buffers hold it, gathered on the CPU: every mesh's vertices and
/// triangles, then every polygonal light's emissive fan, in one vertex and one index array.
#[derive(Default)]
pub(super) struct SceneGeometry {
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    /// Per triangle of the meshes: its 12-index adjacency patch.
    pub patch_indices: Vec<u32>,
    /// Per triangle of the meshes: the triangles across its edges (scene indices), then 0.
    pub triangle_neighbours: Vec<[u32; 4]>,
    /// Per triangle of the meshes: its corners' positions, each a texel, the first's w its
    /// visibility classes ([`class_word`]; every light mixed until the maps are rendered).
    pub triangle_corners: Vec<[[f32; 4]; 3]>,
    /// One per mesh, in scene order.
    pub draws: Vec<DrawCall>,
    /// The material kinds the meshes use, in order of first use (`DrawCall::pipeline`).
    pub kinds: Vec<u32>,
    /// One per polygonal light, in scene order.
    pub emitters: Vec<EmitterDraw>,
    /// Triangles of the meshes; the emitters' come after them (level records cover the meshes
    /// only).
    pub triangle_count: usize,
    /// The point and directional lights ([`gpu_lights`]).
    pub lights: ShaderLights,
    pub materials: Vec<GpuMaterial>,
    pub polygon_lights: Vec<GpuPolygonLight>,
    /// The shadow maps' tiles in the atlas (`shadow_view`).
    pub shadows: ShadowLayout,
}

impl SceneGeometry {
    /// The geometry, lights and materials of `scene`.
    pub(super) fn of(scene: &Scene) -> SceneGeometry {
        let mut geometry = SceneGeometry::default();
        for (mesh_index, mesh) in scene.meshes.iter().enumerate() {
            geometry.add_mesh(scene, mesh_index, mesh);
        }
        let shadows = ShadowLayout::of(scene);
        let lights = gpu_lights(&scene.lights, &shadows.lights);
        let materials: Vec<GpuMaterial> = scene.materials.iter().map(gpu_material).collect();
        let polygon_lights = gpu_polygon_lights(&scene.lights);
        // The emitters' triangles go after the meshes' (level records cover the meshes only).
        let triangle_count = geometry.indices.len() / 3;
        for (light_index, light) in polygon_lights.iter().enumerate() {
            geometry.add_emitter(light_index, light);
        }
        SceneGeometry { triangle_count, lights, materials, polygon_lights, shadows, ..geometry }
    }

    /// Appends mesh `mesh_index` of `scene`: its vertices, triangles, adjacency patches,
    /// neighbours and draw.
    fn add_mesh(&mut self, scene: &Scene, mesh_index: usize, mesh: &Mesh) {
        let base = self.vertices.len() as u32;
        self.vertices.extend(mesh.positions.iter().zip(&mesh.normals).enumerate().map(|(i, (p, n))| {
            Vertex {
                position: p.to_array(),
                normal: n.to_array(),
                uv: mesh.uvs.get(i).map_or([0.0; 2], |uv| uv.to_array()),
            }
        }));
        let first_index = self.indices.len() as u32;
        self.indices.extend(mesh.indices.iter().map(|i| i + base));
        let unknown = class_word(&[Visibility::Mixed; MAX_SHADOWED_LIGHTS as usize]) as f32;
        self.triangle_corners.extend(mesh.indices.chunks_exact(3).map(|t| {
            [0, 1, 2]
                .map(|k| mesh.positions[t[k] as usize].extend(if k == 0 { unknown } else { 0.0 }).to_array())
        }));
        let first_patch_index = self.patch_indices.len() as u32;
        self.patch_indices.extend(adjacency_patches(mesh).iter().map(|i| i + base));
        let first_triangle = first_index / 3;
        self.triangle_neighbours
            .extend(neighbours(mesh).iter().map(|n| [n[0], n[1], n[2], 0].map(|t| t + first_triangle)));
        let kind = material_kind_id(&scene.materials[mesh.material].kind);
        let kinds = &mut self.kinds;
        let pipeline = kinds.iter().position(|&k| k == kind).unwrap_or_else(|| {
            kinds.push(kind);
            kinds.len() - 1
        });
        self.draws.push(DrawCall {
            first_triangle: first_index / 3,
            first_index,
            index_count: mesh.indices.len() as u32,
            first_patch_index,
            one_sided: !mesh.two_sided,
            // With shadows the flat patches are listed: drawn apart by their visibility classes.
            shared_corners: scene.materials[mesh.material].maps.parameter.is_none()
                && scene.shadow_casters.is_empty(),
            material_index: mesh.material as u32,
            mesh_index: mesh_index as u32,
            pipeline,
        });
    }

    /// Appends the emissive fan of polygonal light `light_index`.
    fn add_emitter(&mut self, light_index: usize, light: &GpuPolygonLight) {
        let base = self.vertices.len() as u32;
        let count = light.info.x as u32;
        self.vertices.extend(light.vertices[..count as usize].iter().map(|v| Vertex {
            position: v.truncate().to_array(),
            normal: light.normal.truncate().to_array(),
            uv: [0.0; 2],
        }));
        let first_index = self.indices.len() as u32;
        self.indices.extend((1..count - 1).flat_map(|j| [base, base + j, base + j + 1]));
        self.emitters.push(EmitterDraw {
            first_index,
            index_count: self.indices.len() as u32 - first_index,
            light_index: light_index as u32,
        });
    }
}

/// A triangle's visibility classes by slot as `triangle_shadow_classes` (bindings.glsl) reads
/// them: `SHADOWED_CLASS_BIT` or `MIXED_CLASS_BIT` shifted by the slot.
pub fn class_word(classes: &[Visibility]) -> u32 {
    classes.iter().enumerate().fold(0, |word, (slot, class)| match class {
        Visibility::Lit => word,
        Visibility::Shadowed => word | SHADOWED_CLASS_BIT << slot,
        Visibility::Mixed => word | MIXED_CLASS_BIT << slot,
    })
}

/// `corners` (a triangle's texels of `triangle_corners`, as [`SceneGeometry`] made them) with
/// the first one's w set to each triangle's word of `classes`.
pub fn with_classes(corners: &[[[f32; 4]; 3]], classes: &ShadowClasses) -> Vec<[[f32; 4]; 3]> {
    corners
        .iter()
        .zip(classes.per_triangle())
        .map(|(texels, classes)| {
            let mut texels = *texels;
            texels[0][3] = class_word(classes) as f32;
            texels
        })
        .collect()
}
