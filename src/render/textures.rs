//! The scene's textures on the GPU: every material's albedo map, parameter map and the
//! parameter map's min/max pyramid, uploaded with their mip chains, and one descriptor set per
//! material (set 1 of `glsl/include/bindings.glsl`, bound per draw). A white 1×1 texture
//! stands in where a material has no texture, so every set is fully written.

use crate::error::Result;
use crate::gpu_interface::bindings::forward;
use crate::gpu_types::GpuMaterial;
use crate::scene::texture::MipLevel;
use crate::scene::{Material, MaterialKind, ParameterMapping, Scene};
use crate::vk::memory::Image;
use crate::vk::pipeline::{bind_sampled_images, shader_binding, DescriptorPool};
use crate::vk::texture::{upload_image, LevelData, Sampler};
use crate::vk::Context;
use ash::vk;
use glam::{IVec4, Vec3, Vec4};
use std::sync::Arc;

/// Bindings per material set: albedo map, parameter map, its pyramid.
const MATERIAL_BINDINGS: u32 = forward::MATERIAL_TEXTURES.len() as u32;

/// The uploaded images, their sampler and each material's descriptor set.
pub struct SceneTextures {
    _images: Vec<Image>,
    _sampler: Sampler,
    _pool: DescriptorPool,
    /// One per material, in scene order.
    pub sets: Vec<vk::DescriptorSet>,
}

fn levels_of(levels: &[MipLevel]) -> Vec<LevelData<'_>> {
    levels.iter().map(|l| LevelData { width: l.width, height: l.height, texels: &l.texels }).collect()
}

/// One image of a material's textures, as [`SceneTextures::upload`] uploads it.
pub struct TextureUpload<'a> {
    /// The image's name: what it is and the file it comes from.
    pub name: String,
    pub format: vk::Format,
    /// Its mip chain, level 0 first.
    pub levels: &'a [MipLevel],
    /// The material whose set binds it, and the binding (`forward::MATERIAL_TEXTURES`).
    pub material: usize,
    pub binding: usize,
}

/// Every image the scene's textures upload besides the white stand-in, material by material
/// (a texture that several materials share is uploaded for each).
pub fn uploads(scene: &Scene) -> Vec<TextureUpload<'_>> {
    let mut uploads = Vec::new();
    for (material, m) in scene.materials.iter().enumerate() {
        if let Some(albedo) = &m.maps.albedo {
            uploads.push(TextureUpload {
                name: format!("albedo map {}", albedo.path.display()),
                format: vk::Format::R8G8B8A8_SRGB,
                levels: &albedo.levels,
                material,
                binding: forward::ALBEDO_MAP.binding as usize,
            });
        }
        if let Some(map) = &m.maps.parameter {
            let path = map.texture.path.display();
            uploads.push(TextureUpload {
                name: format!("parameter map {path}"),
                format: vk::Format::R8_UNORM,
                levels: &map.texture.levels,
                material,
                binding: forward::PARAMETER_MAP.binding as usize,
            });
            uploads.push(TextureUpload {
                name: format!("min/max pyramid of {path}"),
                format: vk::Format::R8G8_UNORM,
                levels: &map.pyramid.levels,
                material,
                binding: forward::PARAMETER_PYRAMID.binding as usize,
            });
        }
    }
    uploads
}

/// The layout of a material set: three combined image samplers, every stage.
pub fn material_set_bindings() -> [vk::DescriptorSetLayoutBinding<'static>; MATERIAL_BINDINGS as usize] {
    forward::MATERIAL_TEXTURES.map(|b| shader_binding(b.binding, b.kind.descriptor_type()))
}

impl SceneTextures {
    /// Uploads every material's textures and writes one set of `layout` per material, each
    /// with the shadow atlas `shadow_atlas` (its view, read through its sampler).
    pub fn upload(
        context: &Arc<Context>,
        scene: &Scene,
        layout: vk::DescriptorSetLayout,
        shadow_atlas: (vk::ImageView, vk::Sampler),
    ) -> Result<SceneTextures> {
        let white = [LevelData { width: 1, height: 1, texels: &[255, 255, 255, 255] }];
        let mut images = vec![upload_image(context, "white texture", vk::Format::R8G8B8A8_UNORM, &white)?];
        // Per material: the image index of its albedo map, parameter map and pyramid (0: white).
        let mut slots = vec![[0usize; 3]; scene.materials.len()];
        for upload in uploads(scene) {
            images.push(upload_image(context, &upload.name, upload.format, &levels_of(upload.levels))?);
            slots[upload.material][upload.binding] = images.len() - 1;
        }
        let sampler = Sampler::trilinear_repeat(context, "texture sampler")?;
        let count = scene.materials.len().max(1) as u32;
        let pool = DescriptorPool::new(
            context,
            "material descriptors",
            count,
            &[vk::DescriptorPoolSize {
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                descriptor_count: count * MATERIAL_BINDINGS,
            }],
        )?;
        let mut sets = Vec::with_capacity(slots.len());
        for (index, slot) in slots.iter().enumerate() {
            let set = pool.allocate(layout)?;
            context.name(set, &format!("material {index} textures"));
            // The set was just allocated (idle); views and sampler are kept in `self`.
            let views = slot.map(|image| images[image].view);
            bind_sampled_images(context, set, forward::MATERIAL_TEXTURES[0].binding, sampler.raw, &views);
            bind_sampled_images(
                context,
                set,
                forward::SHADOW_ATLAS.binding,
                shadow_atlas.1,
                &[shadow_atlas.0],
            );
            sets.push(set);
        }
        Ok(SceneTextures { _images: images, _sampler: sampler, _pool: pool, sets })
    }

    /// Whether any material has a texture (the TEXTURED specialization constant).
    pub fn any(scene: &Scene) -> bool {
        scene.materials.iter().any(|m| m.maps.albedo.is_some() || m.maps.parameter.is_some())
    }
}

/// The shaders' view of a material.
pub fn gpu_material(material: &Material) -> GpuMaterial {
    let (diffuse, specular, param) = match material.kind {
        MaterialKind::Lambert { kd } => (kd, Vec3::ZERO, 0.0),
        MaterialKind::BlinnPhong { kd, ks, shininess } => (kd, ks, shininess),
        MaterialKind::Ggx { albedo, f0, roughness } => (albedo, f0, roughness),
    };
    let flag = |present: bool| if present { 0 } else { -1 };
    let (mapping, range) = match &material.maps.parameter {
        Some(map) => {
            (i32::from(map.mapping == ParameterMapping::Exponential), Vec4::new(map.lo, map.hi, 0.0, 0.0))
        }
        None => (0, Vec4::ZERO),
    };
    GpuMaterial {
        diffuse: diffuse.extend(0.0),
        specular: specular.extend(0.0),
        params: Vec4::new(param, 0.0, 0.0, 0.0),
        maps: IVec4::new(
            flag(material.maps.albedo.is_some()),
            flag(material.maps.parameter.is_some()),
            0,
            mapping,
        ),
        parameter_range: range,
    }
}
