//! The preview window's draw: one render pass that puts a float texture (the estimate, or the
//! error map) into the window through `blit.wgsl`.

use bytemuck::{Pod, Zeroable};

/// `Display` of `blit.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct DisplayParams {
    pub offset: [f32; 2],
    pub scale: f32,
    pub exposure: f32,
    pub image_size: [u32; 2],
    pub display_values: u32,
    pub surface_srgb: u32,
}

impl DisplayParams {
    /// The image of `image` pixels centred in a `window`, at the largest integer scale that
    /// fits, or scaled down to fit when even 1 does not.
    pub fn fit(image: [u32; 2], window: [u32; 2]) -> Self {
        let fit = (window[0] as f32 / image[0] as f32).min(window[1] as f32 / image[1] as f32);
        let scale = if fit >= 1.0 { fit.floor() } else { fit };
        let offset = [0, 1].map(|a| ((window[a] as f32 - image[a] as f32 * scale) * 0.5).floor());
        DisplayParams { offset, scale, exposure: 1.0, image_size: image, display_values: 0, surface_srgb: 0 }
    }
}

/// The pipeline and its uniform.
pub struct Blit {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
}

impl Blit {
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("blit"),
            source: wgpu::ShaderSource::Wgsl(include_str!("blit.wgsl").into()),
        });
        let entry =
            |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::FRAGMENT, ty, count: None };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("blit"),
            entries: &[
                entry(
                    0,
                    wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                ),
                // Rgba32Float cannot be filtered without a feature; the shader loads texels.
                entry(
                    1,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                ),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("blit"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("blit"),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL })],
            }),
            multiview_mask: None,
            cache: None,
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("blit params"),
            size: size_of::<DisplayParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self { pipeline, layout, params }
    }

    /// Record the draw of `picture` into `target` with `params`.
    pub fn record(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        picture: &wgpu::Texture,
        target: &wgpu::TextureView,
        params: &DisplayParams,
    ) {
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
        let view = picture.create_view(&wgpu::TextureViewDescriptor::default());
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("blit"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: self.params.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&view) },
            ],
        });
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("blit"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(wgpu::Color::BLACK), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_scales_by_whole_texels_and_centres() {
        let p = DisplayParams::fit([64, 48], [300, 200]);
        assert_eq!(p.scale, 4.0);
        assert_eq!(p.offset, [22.0, 4.0]);
        let small = DisplayParams::fit([512, 512], [256, 128]);
        assert_eq!(small.scale, 0.25);
        assert_eq!(small.offset, [64.0, 0.0]);
    }
}
