// The shaders of maps/q3blend/maps/blends.map (written by maps/q3blend/generate.py): each one
// stage, drawn over what lies behind with its blendFunc, as ioquake3 draws it.

textures/blend/add
{
	surfaceparm trans
	surfaceparm nolightmap
	{
		map textures/blend/add.png
		blendFunc add
	}
}

textures/blend/filter
{
	surfaceparm trans
	surfaceparm nolightmap
	{
		map textures/blend/filter.png
		blendFunc GL_DST_COLOR GL_ZERO
	}
}

textures/blend/blend
{
	surfaceparm trans
	surfaceparm nolightmap
	{
		map textures/blend/blend.png
		blendFunc blend
	}
}
