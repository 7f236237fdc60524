// The shaders of maps/q3map2/shader_light/maps/*.map (tests/render/q3map2_shader_light_test.cpp).

textures/q3map2/ceiling_light
{
	qer_editorimage textures/q3map2/warm
	q3map_surfacelight 1200
	q3map_lightRGB 1 0.5 0.25
	surfaceparm nolightmap
	{
		map textures/q3map2/warm
	}
}

// No q3map_lightRGB: the light image's mean colour.
textures/q3map2/image_light
{
	q3map_surfacelight 900
	q3map_lightImage textures/q3map2/warm.tga
	q3map_backsplash 10 32
	{
		map $lightmap
	}
}

textures/q3map2/sky_sun
{
	surfaceparm sky
	surfaceparm noimpact
	surfaceparm nolightmap
	q3map_sun 1 0.8 0.6 150 30 30
	skyparms - 512 -
}

textures/q3map2/sky_dome
{
	q3map_skylight 200 3
	q3map_lightRGB 0.5 0.75 1
	surfaceparm sky
	surfaceparm noimpact
	skyparms - 512 -
}
